"""The render farm on a real multi-node Ray cluster on this machine (issue 17): a head node and a
second node started with `ray start` on loopback, caustic rendering on llvmpipe, the farm's command
line as a user runs it (caustic-farm --address).

Run by ctest as "farm: multi-node Ray cluster" with the farm's venv (.deps/farm-venv, made by
setup.sh), CAUSTIC_BIN and CAUSTIC_SOURCE_DIR. The cluster is started once for the module; renders
are tiny (40x24, 16 samples). Proven here:
  - 4 sample ranges x 2 crops, rendered on both nodes, merge to the single render within the bound
    of docs/farm.md ((N + n_max + 2) 2^-24 relative per pixel);
  - a sweep of 4 variants gives the same images and contact sheet as `caustic --sweep`;
  - a worker killed in the middle of a task is retried, and after the driver is killed --resume
    renders only the missing part, the image still right;
  - an output folder that holds files is refused (--force writes among them), and a local cluster
    starts in token-authentication mode without Ray's warning about it;
  - a batch's comparison report: relMSE and RMSE equal values computed here from the EXR files,
    HDR-FLIP equals flip-evaluator's on the same files, and the HTML opens in Debian's chromium
    (Playwright, headless) with no console errors, its table sortable and every image loaded.
"""

import glob
import json
import os
from pathlib import Path
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.environ.get("CAUSTIC_SOURCE_DIR", os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(SOURCE_DIR, "app", "farm"))
sys.path.insert(0, os.path.join(SOURCE_DIR, "tests", "cli"))
from caustic_farm.exr import read_exr  # noqa: E402
from test_cli import decode_png  # noqa: E402

BIN = os.environ.get("CAUSTIC_BIN", os.path.join(SOURCE_DIR, "build", "caustic"))
VENV_BIN = os.path.dirname(sys.executable)
CORNELL = os.path.join(SOURCE_DIR, "scenes", "cornell-box.json")
W, H, N = 40, 24, 16
SIZE = ["--width", str(W), "--height", str(H)]
U = 2.0 ** -24
# The farm's package from this checkout (the venv's editable install may point at another one).
FARM_PACKAGE = os.path.join(SOURCE_DIR, "app", "farm")
ENV = dict(os.environ, RAY_AUTH_MODE="disabled", RAY_USAGE_STATS_ENABLED="0", LP_NUM_THREADS="1",
           CAUSTIC_BIN=BIN, PYTHONUNBUFFERED="1",
           PYTHONPATH=os.pathsep.join(p for p in [FARM_PACKAGE, os.environ.get("PYTHONPATH")] if p))


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def png_pixels(path):
    return decode_png(Path(path).read_bytes())[1]


class Farm(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = Path(tempfile.mkdtemp(prefix="cf-"))
        port = free_port()
        cls.address = "127.0.0.1:%d" % port
        ray = os.path.join(VENV_BIN, "ray")
        common = ["--num-cpus", "1", "--num-gpus", "0", "--object-store-memory", "100000000", "--block",
                  "--disable-usage-stats"]
        # Each node in its own process group, so that teardown ends exactly what was started here.
        cls.nodes = [subprocess.Popen([ray, "start", "--head", "--port", str(port), "--node-ip-address", "127.0.0.1",
                                       "--include-dashboard=false", "--temp-dir", str(cls.tmp / "ray"), *common],
                                      env=ENV, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)]
        cls.nodes.append(subprocess.Popen([ray, "start", "--address", cls.address, "--node-ip-address", "127.0.0.1",
                                           *common], env=ENV, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                          start_new_session=True))
        cls.wait_for_nodes(2)
        # The single render every split one must equal.
        subprocess.run([BIN, "--scene", CORNELL, *SIZE, "--samples", str(N), "--exr", "--png", "--output",
                        str(cls.tmp / "whole")], check=True, capture_output=True, env=ENV)
        cls.whole = read_exr(str(cls.tmp / "whole" / "cornell-box.exr"))

    @classmethod
    def wait_for_nodes(cls, count):
        # One probe: connect (retrying until the head is up), then wait for the nodes to join.
        probe = ("import ray, sys, time\n"
                 "for i in range(1200):\n"
                 "    try:\n        ray.init(address=%r, logging_level='ERROR'); break\n"
                 "    except Exception: time.sleep(0.5)\n"
                 "for i in range(1200):\n"
                 "    if sum(n['Alive'] for n in ray.nodes()) >= %d: sys.exit(0)\n"
                 "    time.sleep(0.25)\n"
                 "sys.exit(3)\n" % (cls.address, count))
        deadline = time.monotonic() + 900
        while True:
            if subprocess.run([sys.executable, "-c", probe], env=ENV, capture_output=True).returncode == 0:
                return
            for n in cls.nodes:
                if n.poll() is not None:
                    raise AssertionError("ray start exited with %d" % n.returncode)
            if time.monotonic() > deadline:
                raise AssertionError("the Ray cluster did not come up with %d nodes" % count)
            time.sleep(0.5)

    @classmethod
    def tearDownClass(cls):
        for n in reversed(cls.nodes):
            try:
                os.killpg(n.pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
        for n in cls.nodes:
            try:
                n.wait(timeout=60)
            except subprocess.TimeoutExpired:
                os.killpg(n.pid, signal.SIGKILL)
        # Whatever the nodes started (raylets, agents, workers, a task held by the test hook) is in
        # their sessions (ray start ran with start_new_session): end what is left of those.
        sessions = {n.pid for n in cls.nodes}
        for pid in os.listdir("/proc"):
            if not pid.isdigit():
                continue
            try:
                stat = Path("/proc/%s/stat" % pid).read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[3]) in sessions:   # field 6: the session id
                try:
                    os.kill(int(pid), signal.SIGKILL)
                except ProcessLookupError:
                    pass
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def farm(self, *args, env=None, check=True):
        p = subprocess.run([os.path.join(VENV_BIN, "caustic-farm"), *args, "--address", self.address,
                            "--no-progress"], capture_output=True, text=True, env=dict(ENV, **(env or {})), timeout=1800)
        if check and p.returncode != 0:
            raise AssertionError("caustic-farm %s failed (%d):\n%s" % (" ".join(args), p.returncode, p.stderr))
        return p

    def summary(self, out, stem="cornell-box"):
        return json.loads((out / (stem + ".farm.json")).read_text())

    def assert_equals_whole(self, exr, n_max):
        attrs, w, h, merged = read_exr(str(exr))
        self.assertEqual((w, h, attrs["caustic:samples"]), (W, H, str(N)))
        bound = (N + n_max + 2) * U
        for name in "RGB":
            a, b = merged[name].astype(np.float64), self.whole[3][name].astype(np.float64)
            worst = np.max(np.abs(a - b) - bound * np.maximum(np.abs(a), np.abs(b)))
            self.assertLessEqual(worst, 0.0, name)

    def render_args(self, out, chunks=4, tiles=2):
        return ["render", CORNELL, "--samples", str(N), "--chunks", str(chunks), "--crop-tiles", str(tiles), *SIZE,
                "--exr", "--output", str(out)]

    def test_four_ranges_by_two_crops_on_two_nodes_equal_the_single_render(self):
        out = self.tmp / "split"
        p = self.farm(*self.render_args(out))
        s = self.summary(out)
        self.assertEqual(s["parts"], 8)
        self.assertEqual(len(s["rendered"]), 8)
        self.assertEqual(len(s["nodes"]), 2, s["part_nodes"])   # both nodes rendered parts
        self.assertIn(str(out / "cornell-box.exr"), p.stdout)
        self.assert_equals_whole(out / "cornell-box.exr", n_max=4)
        self.assertFalse((out / ".farm").exists())   # the parts are removed once merged

    def test_a_sweep_of_four_variants_gives_caustics_images(self):
        sweep = ["--sweep", "camera.fov=20,30,40,50"]
        out = self.tmp / "sweep"
        # The scene travels with the job (--ship: Ray uploads the folder as the working_dir).
        self.farm("sweep", CORNELL, *sweep, "--samples", "4", *SIZE, "--output", str(out), "--ship",
                  os.path.dirname(CORNELL))
        ref = self.tmp / "sweep-ref"
        subprocess.run([BIN, "--scene", CORNELL, *sweep, "--samples", "4", *SIZE, "--output", str(ref)], check=True,
                       capture_output=True, env=ENV)
        for name in ["cornell-box-%d.png" % i for i in range(4)] + ["cornell-box-sheet.png"]:
            self.assertEqual(png_pixels(out / name), png_pixels(ref / name), name)
        self.assertEqual(len(self.summary(out, "cornell-box-sweep")["rendered"]), 4)

    def wait_for(self, proc, done, what):
        # Polls for the event; the deadline only turns a hang into a failure that names it.
        deadline = time.monotonic() + 900
        while not done():
            if proc.poll() is not None:
                raise AssertionError("the farm ended before %s:\n%s" % (what, proc.stderr.read()))
            if time.monotonic() > deadline:
                self.fail("still waiting after 900 s until %s: the farm or the cluster hangs" % what)
            time.sleep(0.2)

    def test_a_killed_worker_is_retried_and_resume_after_a_killed_driver_renders_only_what_is_missing(self):
        out, hold = self.tmp / "killed", self.tmp / "hold"
        hold.mkdir()
        # Two sample ranges (the 4 x 2 split is proven above; fewer parts keep this test cheap).
        args = self.render_args(out, chunks=2, tiles=1)
        retried = "cornell-box.part-s0-8-x0-40-y0-24.exr"    # its worker is killed in the task
        missing = "cornell-box.part-s8-16-x0-40-y0-24.exr"   # held while the driver is killed
        for part in (retried, missing):
            (hold / (part + ".hold")).write_text("")
        proc = subprocess.Popen([os.path.join(VENV_BIN, "caustic-farm"), *args, "--address",
                                 self.address, "--no-progress", "--keep-parts"],
                                env=dict(ENV, CAUSTIC_FARM_HOLD_DIR=str(hold)), stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
        pid = lambda part: int((hold / (part + ".pid")).read_text())
        self.wait_for(proc, lambda: (hold / (retried + ".pid")).exists(), "the first held task started")
        os.kill(pid(retried), signal.SIGKILL)   # the Ray worker process running the task
        parts = lambda: glob.glob(str(out / ".farm" / "*" / "*.part-*.exr"))
        self.wait_for(proc, lambda: len(parts()) == 1 and (hold / (missing + ".pid")).exists(),
                      "the first part was done")
        self.assertIn(retried, [os.path.basename(p) for p in parts()])   # rendered again after the kill
        before = {p: os.stat(p).st_mtime_ns for p in parts()}
        proc.kill()   # the driver
        proc.communicate()
        try:
            os.kill(pid(missing), signal.SIGKILL)   # the held task, if Ray has not ended it with its job
        except ProcessLookupError:
            pass
        p = self.farm(*args, "--resume", "--keep-parts")
        self.assertIn("1 of 2 parts are done, rendering 1", p.stderr)
        s = self.summary(out)
        self.assertEqual((s["resumed"], s["rendered"]), (1, [missing]))
        self.assertEqual(before, {p: os.stat(p).st_mtime_ns for p in before})   # not written again
        self.assert_equals_whole(out / "cornell-box.exr", n_max=8)

    def test_refusals(self):
        # A task whose caustic fails stops the farm with the task's name and caustic's message
        # (here a GPU this cluster does not have; the driver's checks cannot see that).
        p = self.farm(*self.render_args(self.tmp / "refused", chunks=2, tiles=1), "--gpu", "5", check=False)
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn("task cornell-box.part-s", p.stderr)
        self.assertIn("--gpu 5: no such GPU", p.stderr)
        self.assertFalse((self.tmp / "refused" / "cornell-box.exr").exists())
        # A folder holding files (here an older render's AOV) is not written into.
        used = self.tmp / "used"
        used.mkdir()
        (used / "cornell-box-albedo.exr").write_bytes(b"older")
        p = self.farm(*self.render_args(used), check=False)
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn("--output %s already holds cornell-box-albedo.exr: each run writes into a folder of its own" % used,
                      p.stderr)
        self.assertEqual(sorted(os.listdir(used)), ["cornell-box-albedo.exr"])
        farm = os.path.join(VENV_BIN, "caustic-farm")
        for args, needle in [
            (["render", CORNELL, "--address", "127.0.0.1:1"], "--address 127.0.0.1:1: no Ray cluster answers there"),
            (["render", CORNELL, "--samples", "4", "--chunks", "5"], "cannot cut 4 into 5 pieces"),
            (["render", CORNELL, "--chunks", "0"], "--chunks: expected at least 1"),
            (["batch", str(self.tmp / "no-jobs.json")], "no-jobs.json"),
        ]:
            p = subprocess.run([farm, *args, "--output", str(self.tmp / "refused")], capture_output=True, text=True,
                               env=ENV, timeout=600)
            self.assertNotEqual(p.returncode, 0, args)
            self.assertIn(needle, p.stderr, args)
            self.assertNotIn("Traceback", p.stderr, args)

    def test_a_local_cluster_starts_with_token_authentication_and_no_warning_and_force_writes_among_files(self):
        # No --address: the farm starts its own Ray cluster, in token mode, which Ray stores in
        # ~/.ray/auth_token (HOME is a folder of the test's here).
        home, out = self.tmp / "home", self.tmp / "local"
        home.mkdir()
        out.mkdir()
        (out / "cornell-box-albedo.exr").write_bytes(b"older")
        env = {k: v for k, v in ENV.items() if k != "RAY_AUTH_MODE"}
        p = subprocess.run([os.path.join(VENV_BIN, "caustic-farm"), "render", CORNELL, "--samples", "4", *SIZE, "--exr",
                            "--local-cpus", "1", "--no-progress", "--force", "--output", str(out)],
                           capture_output=True, text=True, env=dict(env, HOME=str(home)), timeout=1800)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertNotIn("Token authentication", p.stderr)
        self.assertNotIn("RAY_AUTH_MODE", p.stderr)
        self.assertTrue((home / ".ray" / "auth_token").is_file())
        self.assertEqual(self.summary(out)["parts"], 1)
        self.assertEqual(read_exr(str(out / "cornell-box.exr"))[0]["caustic:samples"], "4")
        self.assertEqual((out / "cornell-box-albedo.exr").read_bytes(), b"older")   # --force: left as it was

    def test_batch_report_metrics_and_browser(self):
        out = self.tmp / "batch"
        jobs = self.tmp / "jobs.json"
        jobs.write_text(json.dumps({"args": SIZE, "jobs": [
            {"name": "cornell-4spp", "scene": CORNELL, "args": ["--samples", "4"]},
            {"name": "cornell-narrow", "scene": CORNELL, "args": ["--samples", "4", "--set", "camera.fov=30"]},
        ]}))
        ref = str(self.tmp / "whole" / "cornell-box.exr")
        p = self.farm("batch", str(jobs), "--reference", ref, "--output", str(out))
        rows = {r["name"]: r for r in json.loads((out / "jobs-report.json").read_text())}
        self.assertEqual(set(rows), {"cornell-4spp", "cornell-narrow"})
        import flip_evaluator

        b = self.whole[3]
        for name, row in rows.items():
            a = read_exr(str(out / (name + ".exr")))[3]
            se = rel = 0.0
            for c in "RGB":
                x, y = a[c].astype(np.float64), b[c].astype(np.float64)
                se += float(np.sum((x - y) ** 2))
                rel += float(np.sum((x - y) ** 2 / (y * y + 0.01)))
            self.assertAlmostEqual(row["rmse"], (se / (3 * W * H)) ** 0.5, delta=1e-6 * row["rmse"] + 1e-12)
            self.assertAlmostEqual(row["relmse"], rel / (3 * W * H), delta=1e-6 * row["relmse"] + 1e-15)
            _, flip, _ = flip_evaluator.evaluate(ref, str(out / (name + ".exr")), "HDR")
            self.assertAlmostEqual(row["flip"], flip, places=6)
            self.assertEqual(row["samples"], 4)
        self.assertGreater(rows["cornell-narrow"]["relmse"], 10 * rows["cornell-4spp"]["relmse"])
        csv_lines = (out / "jobs-report.csv").read_text().splitlines()
        self.assertEqual(len(csv_lines), 3)
        self.assertTrue((out / "jobs-sheet.png").exists())

        from playwright.sync_api import sync_playwright

        with sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=shutil.which("chromium") or "/usr/bin/chromium",
                                         args=["--no-sandbox"])
            page = browser.new_page()
            errors = []
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.on("requestfailed", lambda r: errors.append("request failed: " + r.url))
            page.goto((out / "jobs-report.html").as_uri())
            names = lambda: [r.get_attribute("data-name") for r in page.locator("#metrics tbody tr").all()]
            page.click("th[data-key=relmse]")
            self.assertEqual(names(), ["cornell-narrow", "cornell-4spp"])   # the worst first
            page.click("th[data-key=relmse]")
            self.assertEqual(names(), ["cornell-4spp", "cornell-narrow"])
            loaded = page.evaluate("Array.from(document.images).map(i => i.complete && i.naturalWidth > 0)")
            self.assertTrue(loaded and all(loaded), loaded)
            page.click("button[data-view=diff]")
            self.assertTrue(page.locator("[data-view-of=diff]").first.is_visible())
            browser.close()
        self.assertEqual(errors, [])


if __name__ == "__main__":
    unittest.main()
