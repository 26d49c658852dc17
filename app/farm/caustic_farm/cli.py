"""caustic-farm: one render, a sweep or a batch of scenes spread over a Ray cluster.

  caustic-farm render SCENE --samples N --chunks K [--crop-tiles T] [caustic flags]
  caustic-farm sweep SCENE --sweep PATH=V1,V2,... [caustic flags]
  caustic-farm batch JOBS.json [--reference REF]
  caustic-farm compare IMAGE REFERENCE

Flags the farm does not know are caustic's render flags (--width, --set, --seed, ...) and go to
every task; output flags (--png, --exr, --hdr, --half, --aovs, --oidn, ...) go to whatever
writes the images (caustic merge for a split render, the tasks for sweeps and batches).
docs/farm.md has the details: where files must be, GPUs, retries, --resume, the report.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import time

from caustic_farm import plan as planning
from caustic_farm import report
from caustic_farm.exr import check_complete, read_header
from caustic_farm.files import write_atomically

PART_FORMAT = "caustic-part-1"   # app/part_file.h, kPartFormat
PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))


class FarmError(Exception):
    pass


# --- files -----------------------------------------------------------------------------------

def part_problem(path, part):
    """"" when path is a complete part file of exactly this part, else what is wrong with it (the
    merge checks the pixels' checksum again)."""
    if not os.path.isfile(path):
        return "%s: missing" % path
    attrs, w, h, channels, problem = check_complete(path)
    if problem:
        return problem
    expect = {"caustic:part": PART_FORMAT, "caustic:sample_range": part.sample_range, "caustic:crop": part.crop}
    for key, value in expect.items():
        if attrs.get(key) != value:
            return "%s: %s is %r, the plan says %r" % (path, key, attrs.get(key), value)
    if (w, h) != (part.x1 - part.x0, part.y1 - part.y0) or "sum.A" not in channels:
        return "%s: holds %dx%d pixels, the part is %s" % (path, w, h, part.crop)
    return ""


def output_folder(args):
    """--output, or the run's own folder under renders/farm/ (a run's files never mix with
    caustic's own renders in renders/, nor with another run's)."""
    if args.output:
        return args.output
    stem = lambda path: os.path.splitext(os.path.basename(path))[0]
    if args.command == "compare":
        return os.path.join("renders", "farm")
    name = {"render": lambda: stem(args.scene), "sweep": lambda: stem(args.scene) + "-sweep",
            "batch": lambda: stem(args.jobs)}[args.command]()
    return os.path.join("renders", "farm", name)


def refuse_used_folder(args):
    """A render, sweep or batch writes into a folder that holds nothing but the farm's own hidden
    bookkeeping (.farm/ and temporaries), so that nothing is replaced or mixed with older files by
    surprise; --resume (continuing the run whose files are there) and --force write there anyway."""
    if args.command == "compare" or args.resume or args.force or not os.path.isdir(args.output):
        return
    held = sorted(name for name in os.listdir(args.output) if not name.startswith("."))
    if held:
        more = " and %d more" % (len(held) - 5) if len(held) > 5 else ""
        raise FarmError("--output %s already holds %s%s: each run writes into a folder of its own. Give another "
                        "--output, --resume the run those files are from, or --force to write among them (files "
                        "of the same names are replaced, the others are left as they are)"
                        % (args.output, ", ".join(held[:5]), more))


def remove_if_empty(folder):
    try:
        os.rmdir(folder)
    except OSError:
        pass


def output_problem(path):
    """"" when an image the farm wrote looks complete (resume of sweeps and batches)."""
    if not os.path.isfile(path) or os.path.getsize(path) == 0:
        return "%s: missing" % path
    if path.endswith(".exr"):
        return check_complete(path)[4]
    if path.endswith(".png"):
        with open(path, "rb") as f:
            data = f.read()
        if not data.startswith(b"\x89PNG\r\n\x1a\n") or not data.endswith(b"IEND\xaeB`\x82"):
            return "%s: not a complete PNG" % path
    return ""


# --- caustic on the driver -------------------------------------------------------------------

def find_caustic(given):
    for candidate in (given, os.environ.get("CAUSTIC_BIN"),
                      os.path.join(PACKAGE_DIR, "..", "..", "..", "build", "caustic"), shutil.which("caustic")):
        if candidate and os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return os.path.abspath(candidate)
    raise FarmError("no caustic program: build it (./setup.sh build) or give --caustic / $CAUSTIC_BIN")


def run_local(caustic, args):
    p = subprocess.run([caustic, *args], capture_output=True, text=True)
    if p.returncode != 0:
        raise FarmError("caustic %s failed:\n%s" % (" ".join(args), p.stderr.strip()))
    return p


def list_variants(caustic, scene, flags):
    out = run_local(caustic, ["--scene", scene, *flags, "--list-variants"]).stdout
    return [json.loads(line) for line in out.splitlines() if line.strip()]


# --- Ray -------------------------------------------------------------------------------------

def reachable(address, seconds=10.0):
    """Refuses an address whose port takes no connection: ray.init would retry for many minutes."""
    import socket

    host, _, port = address.rpartition(":")
    try:
        with socket.create_connection((host or "127.0.0.1", int(port)), timeout=seconds):
            return
    except (OSError, ValueError) as e:
        raise FarmError("--address %s: no Ray cluster answers there (%s)" % (address, e))


class Cluster:
    """The Ray connection and the one remote function every task runs."""

    def __init__(self, args):
        if not args.address:
            # Ray 2.60 turns token authentication on for a cluster that ray.init() starts while
            # RAY_AUTH_MODE is unset, and warns on every run that it did. The farm sets that mode
            # itself (Ray's documented setting): the same cluster, authenticated, without the
            # warning. A RAY_AUTH_MODE in the user's environment is kept. Set before Ray is
            # imported: Ray reads its configuration once, and a driver still configured without
            # authentication could not talk to the cluster it started.
            os.environ.setdefault("RAY_AUTH_MODE", "token")
        import ray

        self.ray = ray
        runtime_env = {"env_vars": {"RAY_USAGE_STATS_ENABLED": "0"}}
        if args.address:
            # Workers on other machines get this package from the cluster (Ray's py_modules),
            # so they need only Ray, Python and caustic.
            runtime_env["py_modules"] = [PACKAGE_DIR]
        if args.ship:
            runtime_env["working_dir"] = os.path.abspath(args.ship)
        os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
        kwargs = dict(address=args.address or "local", runtime_env=runtime_env, log_to_driver=False,
                      logging_level="WARNING")
        if not args.address:
            kwargs.update(include_dashboard=False, num_cpus=args.local_cpus)
        if args.address and args.address not in ("auto", "local") and "://" not in args.address:
            reachable(args.address)
        try:
            ray.init(**kwargs)
        except Exception as e:   # ConnectionError, a bad address, a cluster of another Ray version
            where = "the Ray cluster at %s" % args.address if args.address else "a local Ray cluster"
            raise FarmError("cannot start or join %s: %s" % (where, e))
        gpus = ray.cluster_resources().get("GPU", 0)
        from caustic_farm.worker import task_entry

        # One GPU per task where the cluster has GPUs, else CPUs (llvmpipe renders on them).
        resources = {"num_gpus": 1} if gpus else {"num_cpus": args.cpus_per_task}
        self.gpus = gpus
        self.nodes = len([n for n in ray.nodes() if n.get("Alive")])
        self.remote = ray.remote(task_entry).options(max_retries=args.max_retries, retry_exceptions=False,
                                                     scheduling_strategy="SPREAD", **resources)

    def shutdown(self):
        self.ray.shutdown()


def run_tasks(cluster, tasks, progress, max_retries):
    """tasks: [{"name", "spec", "accept": f(result) -> problem or "", "weight"}]. Runs them all,
    handing each result to accept as soon as it arrives; a result that accept refuses (a damaged
    file) is rendered again up to max_retries times. Returns {name: result}."""
    ray = cluster.ray
    pending = {}
    attempts = {}

    def submit(t):
        attempts[t["name"]] = attempts.get(t["name"], 0) + 1
        pending[cluster.remote.remote(t["spec"])] = t

    for t in tasks:
        submit(t)
    results = {}
    try:
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            t = pending.pop(ready[0])
            try:
                result = ray.get(ready[0])
            except Exception as e:   # the task's own failure (caustic's message), or lost for good
                cause = getattr(e, "cause", None) or e
                raise FarmError("task %s failed: %s" % (t["name"], cause))
            problem = t["accept"](result)
            if problem:
                if attempts[t["name"]] > max_retries:
                    raise FarmError("task %s: %s (after %d attempts)" % (t["name"], problem, attempts[t["name"]]))
                print("caustic-farm: %s; rendering it again" % problem, file=sys.stderr)
                submit(t)
                continue
            results[t["name"]] = result
            progress(t)
    finally:
        # Only the tasks still running are cancelled: Ray 2.60's core worker aborts the whole
        # process ("Tried to complete task that was not pending", task_manager.cc) when a task is
        # force-cancelled as its own reply arrives, which happened when both tasks of a farm failed
        # at once (tests/farm, test_refusals: the farm died of SIGABRT instead of naming the task).
        # A task that ends between this wait and its cancel can still meet that race.
        if pending:
            done, running = ray.wait(list(pending), num_returns=len(pending), timeout=0)
            for ref in running:
                ray.cancel(ref, force=True)
    return results


class Progress:
    """A tqdm bar over the samples rendered, with the tasks done as its description."""

    def __init__(self, total_weight, tasks, enabled, unit):
        self.bar = None
        self.done, self.tasks = 0, tasks
        if enabled:
            from tqdm import tqdm

            self.bar = tqdm(total=total_weight, unit=unit, unit_scale=True, file=sys.stderr, mininterval=0.5,
                            desc="tasks 0/%d" % tasks)

    def __call__(self, task):
        self.done += 1
        if self.bar:
            self.bar.set_description("tasks %d/%d" % (self.done, self.tasks))
            self.bar.update(task.get("weight", 1))

    def close(self):
        if self.bar:
            self.bar.close()


# --- the commands ----------------------------------------------------------------------------

OUTPUT_SWITCHES = ["png", "hdr", "exr", "half", "aovs", "oidn", "reinhard"]


def output_flags(args):
    flags = ["--" + s for s in OUTPUT_SWITCHES if getattr(args, s)]
    if args.oidn_guides:
        flags += ["--oidn-guides", args.oidn_guides]
    if args.exposure is not None:
        flags += ["--exposure", str(args.exposure)]
    return flags


def scene_arg(args, scene):
    """The scene as the tasks name it: an absolute path (a shared file system), or relative to
    the folder shipped with --ship (the tasks run inside it)."""
    scene = os.path.abspath(scene)
    if not args.ship:
        return scene
    root = os.path.abspath(args.ship)
    if os.path.commonpath([root, scene]) != root:
        raise FarmError("--ship %s: the scene %s is not inside it" % (args.ship, scene))
    return os.path.relpath(scene, root)


def task_spec(args, caustic, name, caustic_args):
    spec = {"caustic": caustic, "args": caustic_args, "name": name,
            "env": {"LP_NUM_THREADS": str(args.cpus_per_task)}}
    if os.environ.get("CAUSTIC_FARM_HOLD_DIR"):
        spec["hold_dir"] = os.environ["CAUSTIC_FARM_HOLD_DIR"]
    return spec


def summary_file(args, stem, summary):
    path = os.path.join(args.output, stem + ".farm.json")
    write_atomically(path, (json.dumps(summary, indent=2) + "\n").encode())
    return path


def cmd_render(args, flags, caustic):
    scene = args.scene
    stem = os.path.splitext(os.path.basename(scene))[0]
    render_flags = list(flags) + (["--samples", str(args.samples)] if args.samples else [])
    (v,) = list_variants(caustic, scene, render_flags)
    try:
        parts = planning.split_render(stem, v["width"], v["height"], v["samples"], args.chunks, args.crop_tiles)
    except ValueError as e:
        raise FarmError("--chunks %d, --crop-tiles %d: %s (%dx%d pixels, %d samples)" %
                        (args.chunks, args.crop_tiles, e, v["width"], v["height"], v["samples"]))
    key = planning.plan_key(os.path.abspath(scene), render_flags, v, args.chunks, args.crop_tiles)
    parts_dir = os.path.join(args.output, ".farm", "%s-%s" % (stem, key))
    if os.path.isdir(parts_dir) and not args.resume:
        shutil.rmtree(parts_dir)
    os.makedirs(parts_dir, exist_ok=True)
    todo, resumed = [], 0
    for p in parts:
        path = os.path.join(parts_dir, p.name)
        if args.resume and not part_problem(path, p):
            resumed += 1
            continue
        if os.path.exists(path):
            os.remove(path)
        todo.append(p)
    if args.resume:
        print("caustic-farm: --resume: %d of %d parts are done, rendering %d" % (resumed, len(parts), len(todo)),
              file=sys.stderr)
    start = time.monotonic()
    nodes, seconds = {}, {}
    rendered = []
    if todo:
        cluster = Cluster(args)
        try:
            def make(p):
                def accept(result):
                    data = result["files"].get(p.name)
                    if data is None:
                        return "%s: caustic wrote %s, not the part" % (p.name, sorted(result["files"]))
                    path = os.path.join(parts_dir, p.name)
                    write_atomically(path, data)
                    problem = part_problem(path, p)
                    if problem:
                        os.remove(path)
                        return problem
                    nodes[p.name] = result.get("node", "")
                    seconds[p.name] = result["seconds"]
                    rendered.append(p.name)
                    return ""
                spec = task_spec(args, caustic, p.name, ["--scene", scene_arg(args, scene), *render_flags,
                                                          "--sample-range", p.sample_range, "--crop", p.crop])
                return {"name": p.name, "spec": spec, "accept": accept, "weight": p.pixel_samples}

            tasks = [make(p) for p in todo]
            bar = Progress(sum(t["weight"] for t in tasks), len(tasks), not args.no_progress, "samples")
            try:
                run_tasks(cluster, tasks, bar, args.max_retries)
            finally:
                bar.close()
            gpus = cluster.gpus
        finally:
            cluster.shutdown()
    else:
        gpus = 0
    render_wall = time.monotonic() - start
    out = os.path.join(args.output, stem)
    merged = run_local(caustic, ["merge", out, *[os.path.join(parts_dir, p.name) for p in parts], *output_flags(args)])
    written = [line for line in merged.stdout.splitlines() if line.strip()]
    summary = {"scene": scene, "width": v["width"], "height": v["height"], "samples": v["samples"],
               "parts": len(parts), "rendered": sorted(rendered), "resumed": resumed,
               "nodes": sorted(set(nodes.values())), "part_nodes": nodes, "part_seconds": seconds,
               "gpus": gpus, "render_wall_seconds": render_wall, "outputs": written}
    if not args.keep_parts:
        shutil.rmtree(parts_dir, ignore_errors=True)
        remove_if_empty(os.path.dirname(parts_dir))
    if args.reference:
        exr = [w for w in written if w.endswith(".exr")]
        if not exr:
            raise FarmError("--reference needs an EXR of the render: add --exr")
        summary["report"] = make_report(args, caustic, [report_item(stem, exr[0], written, v, sum(seconds.values()))],
                                        args.reference, os.path.join(args.output, stem))
    for w in written + list(summary.get("report", {}).values()):
        print(w)
    print(summary_file(args, stem, summary))
    print("caustic-farm: %s: %d parts (%d rendered, %d resumed) on %d node(s) in %.1f s; merged into %s" %
          (stem, len(parts), len(rendered), resumed, len(summary["nodes"]), render_wall, ", ".join(written)),
          file=sys.stderr)
    return 0


def run_whole_renders(args, caustic, jobs, key_items, label):
    """Jobs of whole renders (sweep variants, batch scenes), one task each: {"name", "args",
    "rename": f(file name) -> output file name}. Returns ({name: [files written]}, summary)."""
    manifest_path = os.path.join(args.output, ".farm", "%s-%s.json" % (label, planning.plan_key(*key_items)))
    manifest = {}
    if args.resume and os.path.isfile(manifest_path):
        with open(manifest_path) as f:
            manifest = json.load(f)
    done = {name: files for name, files in manifest.items()
            if name in {j["name"] for j in jobs} and files and not any(output_problem(p) for p in files)}
    todo = [j for j in jobs if j["name"] not in done]
    if args.resume:
        print("caustic-farm: --resume: %d of %d tasks are done, rendering %d" % (len(done), len(jobs), len(todo)),
              file=sys.stderr)
    nodes, seconds = {}, {}
    start = time.monotonic()
    if todo:
        cluster = Cluster(args)
        try:
            def make(j):
                def accept(result):
                    files = []
                    for name, data in sorted(result["files"].items()):
                        path = os.path.join(args.output, j["rename"](name))
                        write_atomically(path, data)
                        problem = output_problem(path)
                        if problem:
                            return problem
                        files.append(path)
                    done[j["name"]] = files
                    nodes[j["name"]] = result.get("node", "")
                    seconds[j["name"]] = result["seconds"]
                    write_atomically(manifest_path, json.dumps(done, indent=1).encode())
                    return ""
                return {"name": j["name"], "spec": task_spec(args, caustic, j["name"], j["args"]), "accept": accept,
                        "weight": 1}

            tasks = [make(j) for j in todo]
            bar = Progress(len(tasks), len(tasks), not args.no_progress, "task")
            try:
                run_tasks(cluster, tasks, bar, args.max_retries)
            finally:
                bar.close()
        finally:
            cluster.shutdown()
    summary = {"tasks": len(jobs), "rendered": sorted(nodes), "resumed": len(jobs) - len(todo),
               "nodes": sorted(set(nodes.values())), "task_nodes": nodes, "task_seconds": seconds,
               "render_wall_seconds": time.monotonic() - start}
    return done, summary


def make_sheet(caustic, out_png, columns, cells):
    layout = os.path.join(os.path.dirname(out_png), "." + os.path.basename(out_png) + ".layout.json")
    write_atomically(layout, json.dumps({"output": os.path.abspath(out_png), "columns": columns,
                                         "cells": [{"image": os.path.abspath(i), "label": l} for i, l in cells]}).encode())
    try:
        run_local(caustic, ["sheet", layout])
    finally:
        os.remove(layout)
    return out_png


def cmd_sweep(args, flags, caustic):
    scene = args.scene
    stem = os.path.splitext(os.path.basename(scene))[0]
    sweeps = [a for s in args.sweep for a in ("--sweep", s)]
    render_flags = list(flags) + (["--samples", str(args.samples)] if args.samples else []) + sweeps
    variants = list_variants(caustic, scene, render_flags)
    outputs = output_flags(args)
    if "--png" not in outputs:
        outputs.append("--png")   # the contact sheet's cells
    jobs = [{"name": "variant %d" % v["index"],
             "args": ["--scene", scene_arg(args, scene), *render_flags, "--variant", str(v["index"]), *outputs],
             "rename": lambda n: n} for v in variants]
    done, summary = run_whole_renders(args, caustic, jobs, [os.path.abspath(scene), render_flags, outputs],
                                      stem + "-sweep")
    written = [p for j in jobs for p in done[j["name"]]]
    pngs = [os.path.join(args.output, stem + v["suffix"] + ".png") for v in variants]
    if all(os.path.isfile(p) for p in pngs):
        written.append(make_sheet(caustic, os.path.join(args.output, stem + "-sheet.png"), variants[0]["columns"],
                                  [(p, v["label"]) for p, v in zip(pngs, variants)]))
    if args.reference:
        items = []
        for v in variants:
            exr = os.path.join(args.output, stem + v["suffix"] + ".exr")
            if not os.path.isfile(exr):
                raise FarmError("--reference needs EXR renders: add --exr")
            items.append(report_item(v["label"].replace("\n", " ") or stem, exr, written, v,
                                     summary["task_seconds"].get("variant %d" % v["index"])))
        summary["report"] = make_report(args, caustic, items, args.reference, os.path.join(args.output, stem + "-sweep"))
    summary["outputs"] = written
    for w in written + list(summary.get("report", {}).values()):
        print(w)
    print(summary_file(args, stem + "-sweep", summary))
    print("caustic-farm: %s: %d variants (%d rendered, %d resumed) on %d node(s)" %
          (stem, len(jobs), len(summary["rendered"]), summary["resumed"], len(summary["nodes"])), file=sys.stderr)
    return 0


def load_jobs(path):
    """JOBS.json: {"jobs": [{"name": "cornell", "scene": "scenes/cornell-box.json",
    "args": ["--samples", "64"], "reference": "refs/cornell.exr"}], "args": [...for every job]};
    paths relative to the file's folder."""
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, ValueError) as e:
        raise FarmError("%s: %s" % (path, e))
    folder = os.path.dirname(os.path.abspath(path))
    if not isinstance(data, dict) or not isinstance(data.get("jobs"), list) or not data["jobs"]:
        raise FarmError("%s: expected {\"jobs\": [...]} with at least one job" % path)
    unknown = set(data) - {"jobs", "args"}
    if unknown:
        raise FarmError("%s: unknown key(s) %s" % (path, ", ".join(sorted(unknown))))
    common = data.get("args", [])
    jobs, names = [], set()
    for i, j in enumerate(data["jobs"]):
        where = "%s: jobs[%d]" % (path, i)
        if not isinstance(j, dict) or not isinstance(j.get("scene"), str):
            raise FarmError("%s: expected an object with a \"scene\"" % where)
        if set(j) - {"name", "scene", "args", "reference"}:
            raise FarmError("%s: unknown key(s) %s" % (where, ", ".join(sorted(set(j) - {"name", "scene", "args", "reference"}))))
        args = j.get("args", [])
        if not isinstance(args, list) or not all(isinstance(a, str) for a in args):
            raise FarmError("%s.args: expected a list of strings" % where)
        name = j.get("name") or os.path.splitext(os.path.basename(j["scene"]))[0]
        if not name.replace("-", "").replace("_", "").replace(".", "").isalnum() or name in names:
            raise FarmError("%s.name: %r is not a unique name of letters, digits, '-', '_' and '.'" % (where, name))
        names.add(name)
        ref = j.get("reference")
        jobs.append({"name": name, "scene": os.path.join(folder, j["scene"]), "args": list(common) + args,
                     "reference": os.path.join(folder, ref) if ref else None})
    return jobs


def cmd_batch(args, flags, caustic):
    jobs = load_jobs(args.jobs)
    stem = os.path.splitext(os.path.basename(args.jobs))[0]
    outputs = output_flags(args)
    for needed in ("--png", "--exr"):   # the sheet's cells and the report's metrics
        if needed not in outputs:
            outputs.append(needed)
    tasks = []
    for j in jobs:
        scene_stem = os.path.splitext(os.path.basename(j["scene"]))[0]
        tasks.append({"name": j["name"],
                      "args": ["--scene", scene_arg(args, j["scene"]), *flags, *j["args"], *outputs],
                      "rename": (lambda s, n: lambda f: n + f[len(s):] if f.startswith(s) else n + "-" + f)(scene_stem, j["name"])})
    done, summary = run_whole_renders(args, caustic, tasks, [os.path.abspath(args.jobs), flags, outputs,
                                                             [(j["name"], j["scene"], j["args"]) for j in jobs]], stem)
    written = [p for j in jobs for p in done[j["name"]]]
    cells = [(os.path.join(args.output, j["name"] + ".png"), j["name"]) for j in jobs]
    written.append(make_sheet(caustic, os.path.join(args.output, stem + "-sheet.png"), min(4, len(jobs)), cells))
    if args.reference or any(j["reference"] for j in jobs):
        items = []
        for j in jobs:
            ref = j["reference"] or reference_for(args.reference, j["name"])
            items.append(report_item(j["name"], os.path.join(args.output, j["name"] + ".exr"), written, None,
                                     summary["task_seconds"].get(j["name"]), reference=ref))
        summary["report"] = make_report(args, caustic, items, None, os.path.join(args.output, stem))
    summary["outputs"] = written
    for w in written + list(summary.get("report", {}).values()):
        print(w)
    print(summary_file(args, stem, summary))
    print("caustic-farm: %s: %d jobs (%d rendered, %d resumed) on %d node(s)" %
          (stem, len(jobs), len(summary["rendered"]), summary["resumed"], len(summary["nodes"])), file=sys.stderr)
    return 0


# --- comparisons -----------------------------------------------------------------------------

def reference_for(reference, name):
    """--reference REF: a file (one reference for every image) or a folder of <name>.exr."""
    if reference is None:
        return None
    if os.path.isdir(reference):
        return os.path.join(reference, name + ".exr")
    return reference


def report_item(name, exr, written, variant, seconds, reference=None):
    samples = None
    try:
        attrs = read_header(exr)
        samples = int(attrs.get("caustic:samples", "0")) or None
        if seconds is None and "caustic:render_seconds" in attrs:
            seconds = float(attrs["caustic:render_seconds"])
    except (OSError, RuntimeError, ValueError):
        pass
    return {"name": name, "image": exr, "reference": reference, "seconds": seconds, "samples": samples}


def make_report(args, caustic, items, reference, stem):
    for it in items:
        if it["reference"] is None:
            it["reference"] = reference_for(reference, it["name"]) if reference else None
        if it["reference"] is None or not os.path.isfile(it["reference"]):
            raise FarmError("%s: no reference image %s" % (it["name"], it["reference"]))
    return report.write_report(caustic, items, stem)


def cmd_compare(args, flags, caustic):
    if flags:
        raise FarmError("compare: unknown option(s) %s" % " ".join(flags))
    name = os.path.splitext(os.path.basename(args.image))[0]
    item = report_item(name, args.image, [], None, None, reference=args.reference_image)
    paths = make_report(args, caustic, [item], None, os.path.join(args.output, name + "-compare"))
    for p in paths.values():
        print(p)
    return 0


# --- the command line ------------------------------------------------------------------------

def parser():
    # No abbreviations: a caustic flag the farm does not know must never be taken for the start of
    # one of the farm's own.
    common = argparse.ArgumentParser(add_help=False, allow_abbrev=False)
    g = common.add_argument_group("farm")
    g.add_argument("--output", help="output folder, which must hold no files yet (default: renders/farm/<scene>, "
                                    "<scene>-sweep or <jobs file>; compare: renders/farm)")
    g.add_argument("--force", action="store_true",
                   help="write into an output folder that already holds files (same names are replaced)")
    g.add_argument("--address", help="join this Ray cluster (host:port, or 'auto'); default: start a local one")
    g.add_argument("--resume", action="store_true", help="keep the parts or images a killed run left, render the rest")
    g.add_argument("--max-retries", type=int, default=3, help="retries of a task whose worker died (default 3)")
    g.add_argument("--caustic", help="the caustic program, at the same path on every node (default: build/caustic)")
    g.add_argument("--cpus-per-task", type=int, default=1,
                   help="CPUs a task asks for where the cluster has no GPUs (llvmpipe threads; default 1)")
    g.add_argument("--local-cpus", type=int, help="CPUs of the local cluster (default: all)")
    g.add_argument("--ship", metavar="DIR",
                   help="upload DIR (holding the scene and its files) to the cluster with the job (Ray's "
                        "runtime_env working_dir) instead of reading the scene from a shared path")
    g.add_argument("--reference", help="compare with this reference (an EXR, or a folder of <name>.exr) and write a report")
    g.add_argument("--no-progress", action="store_true", help="no progress bar")
    o = common.add_argument_group("outputs (as caustic's)")
    for s in OUTPUT_SWITCHES:
        o.add_argument("--" + s, action="store_true")
    o.add_argument("--oidn-guides")
    o.add_argument("--exposure", type=float)
    p = argparse.ArgumentParser(prog="caustic-farm", description=__doc__.split("\n\n")[0], allow_abbrev=False,
                                formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__.split("\n\n", 1)[1])
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("render", parents=[common], allow_abbrev=False, help="one render split into parts")
    r.add_argument("scene")
    r.add_argument("--samples", type=int, help="samples per pixel (default: the scene's)")
    r.add_argument("--chunks", type=int, default=1, help="sample ranges (default 1)")
    r.add_argument("--crop-tiles", type=int, default=1, help="crops of the image (default 1)")
    r.add_argument("--keep-parts", action="store_true", help="keep the part files after merging")
    s = sub.add_parser("sweep", parents=[common], allow_abbrev=False, help="one task per variant of --sweep, and the contact sheet")
    s.add_argument("scene")
    s.add_argument("--sweep", action="append", required=True, help="as caustic's --sweep (repeatable)")
    s.add_argument("--samples", type=int)
    b = sub.add_parser("batch", parents=[common], allow_abbrev=False, help="one task per job of JOBS.json, the sheet and the report")
    b.add_argument("jobs")
    c = sub.add_parser("compare", parents=[common], allow_abbrev=False, help="the comparison report of one image against a reference")
    c.add_argument("image")
    c.add_argument("reference_image")
    return p


def main(argv=None):
    p = parser()
    args, flags = p.parse_known_args(argv)
    for name in ("max_retries", "cpus_per_task", "local_cpus", "chunks", "crop_tiles"):
        value = getattr(args, name, None)
        if value is not None and value < (0 if name == "max_retries" else 1):
            p.error("--%s: expected at least %d, got %d" % (name.replace("_", "-"), 0 if name == "max_retries" else 1, value))
    try:
        caustic = find_caustic(args.caustic)
        # Which program the tasks run: with several checkouts, a farm installed from another one
        # finds that checkout's build/caustic (docs/farm.md).
        print("caustic-farm: caustic is %s" % caustic, file=sys.stderr)
        args.output = output_folder(args)
        refuse_used_folder(args)
        os.makedirs(args.output, exist_ok=True)
        return {"render": cmd_render, "sweep": cmd_sweep, "batch": cmd_batch, "compare": cmd_compare}[args.command](
            args, flags, caustic)
    except FarmError as e:
        print("caustic-farm: error: %s" % e, file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("caustic-farm: interrupted (--resume continues)", file=sys.stderr)
        return 130
