"""The comparison report: per image relMSE and RMSE (from `caustic compare`, so one definition
serves the command line and the farm) and HDR-FLIP (NVIDIA's flip-evaluator, Andersson et al.
2021, "Visualizing Errors in Rendered High Dynamic Range Images"), with false-colour maps, in one
self-contained HTML file (images inlined as data: URLs, no script or style from elsewhere), and
the same figures as JSON and CSV."""

import base64
import csv
import html
import io
import json
import os
import struct
import subprocess
import tempfile
import zlib

from caustic_farm.files import write_atomically


def png_bytes(rgb8, width, height):
    """An 8-bit RGB PNG from rows of bytes (numpy uint8 array H x W x 3)."""
    raw = b"".join(b"\0" + rgb8[y].tobytes() for y in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def to_display(linear):
    """Linear RGB -> 8-bit sRGB of the clamped values (the same for images and references, so
    side-by-side views compare like with like; caustic's PNGs use a tone curve instead)."""
    import numpy as np

    x = np.clip(np.nan_to_num(linear, nan=0.0, posinf=1.0), 0.0, 1.0)
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return np.round(s * 255).astype(np.uint8)


def data_url(png):
    return "data:image/png;base64," + base64.b64encode(png).decode()


def compare_one(caustic, item, workdir):
    """The figures and images of one image against its reference."""
    import flip_evaluator
    import numpy as np

    map_path = os.path.join(workdir, "relmse-%d.png" % id(item))
    p = subprocess.run([caustic, "compare", item["image"], item["reference"], "--map", map_path],
                       capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(p.stderr.strip())
    metrics = json.loads(p.stdout)
    test = flip_evaluator.load(item["image"])
    ref = flip_evaluator.load(item["reference"])
    flip_map, flip_mean, _ = flip_evaluator.evaluate(ref, test, "HDR")
    h, w = test.shape[:2]
    with open(map_path, "rb") as f:
        relmse_png = f.read()
    diff = np.abs(test.astype(np.float64) - ref.astype(np.float64))
    images = {
        "image": png_bytes(to_display(test), w, h),
        "reference": png_bytes(to_display(ref), w, h),
        "flip": png_bytes(np.round(np.clip(flip_map, 0, 1) * 255).astype(np.uint8), w, h),
        "relmse": relmse_png,
        "difference": png_bytes(to_display(diff * 4.0), w, h),
    }
    row = {"name": item["name"], "image": item["image"], "reference": item["reference"], "width": w, "height": h,
           "relmse": metrics["relmse"], "rmse": metrics["rmse"], "flip": float(flip_mean),
           "max_abs": metrics["max_abs"], "samples": item.get("samples"), "seconds": item.get("seconds")}
    return row, images


PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>caustic comparison report</title>
<style>
body{font:14px system-ui,sans-serif;margin:1.5em;background:#fafafa;color:#222}
table{border-collapse:collapse}th,td{padding:4px 10px;border-bottom:1px solid #ddd;text-align:right}
th{cursor:pointer;background:#eee;user-select:none}th.sorted::after{content:" \\25BE"}
td.name,th.name{text-align:left}img.thumb{height:48px;image-rendering:pixelated}
section{margin:2em 0}figure{display:inline-block;margin:0 8px 8px 0}figcaption{text-align:center}
section img{width:256px;image-rendering:pixelated;border:1px solid #ccc}
.views button{margin-right:4px}.hidden{display:none}
</style></head><body>
<h1>caustic comparison report</h1>
<p>relMSE = mean((a - b)<sup>2</sup> / (b<sup>2</sup> + 0.01)) and RMSE over all pixels and channels, from
<code>caustic compare</code>; HDR-FLIP is NVIDIA's FLIP (flip-evaluator, HDR mode, default viewing conditions),
its mean over the image. Click a column to sort. Maps: FLIP (magma), relMSE per pixel (log scale, 1e-4 black to 1
white), |a - b| x 4.</p>
<table id="metrics"><thead><tr><th class="name" data-key="name">image</th><th>thumbnail</th>
<th data-key="relmse">relMSE</th><th data-key="rmse">RMSE</th><th data-key="flip">HDR-FLIP</th>
<th data-key="samples">samples</th><th data-key="seconds">render s</th></tr></thead><tbody>
@ROWS@
</tbody></table>
<div class="views">view: <button data-view="side">side by side</button><button data-view="diff">differences</button></div>
@SECTIONS@
<script>
(function () {
  var table = document.getElementById("metrics"), body = table.tBodies[0];
  Array.prototype.forEach.call(table.tHead.rows[0].cells, function (th) {
    if (!th.dataset.key) return;
    th.addEventListener("click", function () {
      // The first click sorts by the largest value first (the worst error on top), the next reverses.
      var key = th.dataset.key, rows = Array.prototype.slice.call(body.rows);
      var order = th.dataset.order === "desc" ? "asc" : "desc";
      rows.sort(function (a, b) {
        var x = a.dataset[key], y = b.dataset[key];
        var nx = parseFloat(x), ny = parseFloat(y);
        var c = (isNaN(nx) || isNaN(ny)) ? String(x).localeCompare(String(y)) : nx - ny;
        return order === "desc" ? -c : c;
      });
      Array.prototype.forEach.call(table.querySelectorAll("th"), function (h) {
        h.classList.remove("sorted");
        delete h.dataset.order;
      });
      th.classList.add("sorted");
      th.dataset.order = order;
      rows.forEach(function (r) { body.appendChild(r); });
    });
  });
  Array.prototype.forEach.call(document.querySelectorAll(".views button"), function (b) {
    b.addEventListener("click", function () {
      var view = b.dataset.view;
      Array.prototype.forEach.call(document.querySelectorAll("[data-view-of]"), function (e) {
        e.classList.toggle("hidden", e.dataset.viewOf !== view);
      });
    });
  });
})();
</script>
</body></html>
"""


def fmt(x, spec):
    return "" if x is None else format(x, spec)


def write_report(caustic, items, stem):
    """Writes <stem>-report.html, .json and .csv; returns their paths."""
    rows, sections, table = [], [], []
    with tempfile.TemporaryDirectory(prefix="caustic-report-") as work:
        for i, item in enumerate(items):
            row, images = compare_one(caustic, item, work)
            table.append(row)
            e = html.escape
            rows.append(
                '<tr data-name="{n}" data-relmse="{r}" data-rmse="{m}" data-flip="{f}" data-samples="{s}" '
                'data-seconds="{t}"><td class="name"><a href="#item{i}">{n}</a></td>'
                '<td><img class="thumb" alt="{n}" src="{thumb}"></td><td>{rs}</td><td>{ms}</td><td>{fs}</td>'
                '<td>{s}</td><td>{ts}</td></tr>'.format(
                    n=e(row["name"]), i=i, r=row["relmse"], m=row["rmse"], f=row["flip"], s=row["samples"] or "",
                    t=row["seconds"] if row["seconds"] is not None else "", thumb=data_url(images["image"]),
                    rs=fmt(row["relmse"], ".4g"), ms=fmt(row["rmse"], ".4g"), fs=fmt(row["flip"], ".4f"),
                    ts=fmt(row["seconds"], ".2f")))

            def fig(key, caption):
                return '<figure><img alt="{c}" src="{u}"><figcaption>{c}</figcaption></figure>'.format(
                    c=caption, u=data_url(images[key]))

            sections.append(
                '<section id="item{i}"><h2>{n}</h2><p>{img} against {ref}: relMSE {r}, RMSE {m}, HDR-FLIP {f}</p>'
                '<div data-view-of="side">{a}{b}{c}{d}</div><div data-view-of="diff" class="hidden">{x}{c}{d}</div>'
                '</section>'.format(
                    i=i, n=e(row["name"]), img=e(row["image"]), ref=e(row["reference"]), r=fmt(row["relmse"], ".4g"),
                    m=fmt(row["rmse"], ".4g"), f=fmt(row["flip"], ".4f"), a=fig("image", "image"),
                    b=fig("reference", "reference"), c=fig("flip", "HDR-FLIP"), d=fig("relmse", "relMSE"),
                    x=fig("difference", "|image - reference| x 4")))
    page = PAGE.replace("@ROWS@", "\n".join(rows)).replace("@SECTIONS@", "\n".join(sections))
    paths = {"html": stem + "-report.html", "json": stem + "-report.json", "csv": stem + "-report.csv"}
    write_atomically(paths["html"], page.encode())
    write_atomically(paths["json"], (json.dumps(table, indent=2) + "\n").encode())
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(table[0].keys()))
    w.writeheader()
    w.writerows(table)
    write_atomically(paths["csv"], buf.getvalue().encode())
    return paths
