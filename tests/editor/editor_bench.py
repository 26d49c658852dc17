#!/usr/bin/env python3
"""The editor's responsiveness benchmark (not a test): runs the real editor under xvfb-run on a
scene at a given resolution with a scripted session (converge a little, a 20-frame gizmo drag, a
translate, an orbit, each followed by rendering) and prints the script's report: frame times
while rendering (median, p95, max), all frames, and the time from each edit to the first frame
that shows it. Figures go to docs/performance.md with the machine and its load.

With --build it measures program builds instead (issue 41): for each repro action that needs a
new integrator program (the gold preset, a rect light, an HDR map, opening another scene), in a
session of its own, built on the window's thread ($CAUSTIC_BACKGROUND_BUILDS=0: the "before") and
in the background: the longest frame after the action, the frames drawn with "Building
shaders...", and the time from the action to N spp. --cold turns Mesa's shader cache and
caustic's program cache off.

With --converge N it measures convergence instead (issue 15): an idle editor (`idle on`: the
pacing of a session nobody touches, which gives the path tracer 250 ms a frame) renders the scene
to N spp at its output resolution, and batch mode (`caustic --scene ...` at N spp) renders the
same, as it is and with CAUSTIC_BAKE_GEOMETRY=0 (the editor's program: batch mode bakes a scene of
a few primitives into its program on llvmpipe, the editor does not); it prints the render times
(the editor's from the render's start to N spp, batch mode's "N spp in X s", neither counting
start-up) and the ratios (the goal: within 1.5x).

    tests/editor/editor_bench.py [--size N] [--scene FILE] [--bin build/caustic] [--converge N]
"""
import argparse
import contextlib
import json
import os
import re
import subprocess
import sys
import tempfile

from test_editor_e2e import xvfb_run  # the editor's own exit status under xvfb-run

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))

SCRIPT = """
wait_samples 2
select object "small box"
drag 0.3 0 0 20
wait_samples 3
translate -0.2 0 0
wait_samples 4
orbit 10 0
wait_samples 6
report report.json
quit
"""


# --build: each of issue 41's repro actions that needs a new integrator program, in a session of
# its own: the longest frame after the action, the frames drawn with "Building shaders...", and
# the time from the action to 4 spp at the viewport's panel size (16 for the gold preset, as
# measured before).
BUILD_SCRIPT = """
viewport panel
viewport_scale {scale}
wait_samples 2
{action}
record_sizes
wait_samples {samples}
report report.json
quit
"""

BUILD_ACTIONS = [
    ("gold preset", "select material white\napply_preset gold", 16),
    ("add a rect light", "add_light rect", 4),
    ("pick an HDR map", "select environment\npick_file environment {hdr}", 4),
    ("open a scene", "open {other}\nwait_open", 4),
]

CONVERGE_SCRIPT = """
idle on
{denoise}
wait_samples {n}
report report.json
quit
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "cornell-box.json"))
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "caustic"))
    ap.add_argument("--converge", type=int, default=0, help="compare an idle editor's time to N spp with batch mode's")
    ap.add_argument("--idle-denoise", action="store_true", help="with --converge: leave Denoise when idle on (the default in the editor)")
    ap.add_argument("--build", action="store_true", help="the longest frame after each repro action that builds a program, "
                    "built on the window's thread and in the background")
    ap.add_argument("--cold", action="store_true", help="with --build: Mesa's shader cache and caustic's program cache off")
    ap.add_argument("--hdr", default="sky.hdr", help="with --build: the environment map as the picker lists it")
    ap.add_argument("--scale", default="1", help="with --build: the viewport scale (auto, 1, 0.5, 0.25)")
    args = ap.parse_args()
    if args.build:
        return build_table(args)
    with scene_copy(args, args.converge or None) as scene_file:
        script = CONVERGE_SCRIPT.format(n=args.converge, denoise="" if args.idle_denoise else "denoise_idle off") \
            if args.converge else SCRIPT
        report = run_session(args, scene_file, script, {})
        if args.converge:
            # Batch mode as it is (the geometry baked into its program on llvmpipe), and with the
            # editor's own program (CAUSTIC_BAKE_GEOMETRY=0).
            batch = {label: run_batch(args, scene_file, env) for label, env in
                     (("batch", {}), ("batch, no baking", {"CAUSTIC_BAKE_GEOMETRY": "0"}))}
    if args.converge:
        editor_s = report["render_elapsed_seconds"]
        print(f"scene {os.path.basename(args.scene)} at {report['width']} x {report['height']}, {args.converge} spp")
        print(f"{'editor (idle)':24} {editor_s:.2f} s")
        for label, seconds in batch.items():
            print(f"{label:24} {seconds:.2f} s   editor / it {editor_s / seconds:.2f}x (goal: 1.5x or less)")
        print(f"load average            {os.getloadavg()[0]:.2f}")
        return
    keys = ["width", "height", "rendering_frames", "frame_ms_median", "frame_ms_p95", "frame_ms_max",
            "all_frames_ms_median", "frame_overhead_ms_median", "overhead_ms_median", "samples_per_frame_mean", "edit_to_frame_ms_median", "edit_to_frame_ms"]
    for k in keys:
        print(f"{k:24} {report.get(k)}")


@contextlib.contextmanager
def scene_copy(args, samples=None):
    """The scene at --size (and `samples`), written beside the original so that its relative file
    names stay valid; removed afterwards."""
    with open(args.scene) as f:
        scene = json.load(f)
    scene.setdefault("render", {})["width"] = args.size
    scene["render"]["height"] = args.size
    if samples:
        scene["render"]["samples"] = samples
    scene_file = os.path.join(os.path.dirname(os.path.abspath(args.scene)), f".editor-bench-{os.getpid()}.json")
    with open(scene_file, "w") as f:
        json.dump(scene, f)
    try:
        yield scene_file
    finally:
        os.remove(scene_file)


def run_batch(args, scene_file, extra_env):
    """caustic --scene at the scene's samples; returns its render time ("N spp in X s")."""
    with tempfile.TemporaryDirectory(prefix="caustic-editor-bench-") as tmp:
        batch = subprocess.run([args.bin, "--scene", scene_file, "--output", tmp], env=dict(os.environ, **extra_env),
                               capture_output=True, text=True, timeout=3600)
    if batch.returncode != 0:
        sys.exit(f"editor_bench: batch mode failed ({batch.returncode}):\n{batch.stderr[-2000:]}")
    m = re.search(r"(\d+) spp in ([0-9.]+) s", batch.stderr)
    if not m:
        sys.exit("editor_bench: no 'N spp in X s' in batch mode's output:\n" + batch.stderr[-2000:])
    return float(m.group(2))


def run_session(args, scene_path, script_text, extra_env):
    """One editor session under xvfb-run on scene_path with the script; returns its report."""
    with tempfile.TemporaryDirectory(prefix="caustic-editor-bench-") as tmp:
        script = os.path.join(tmp, "script.txt")
        with open(script, "w") as f:
            f.write(script_text)
        env = dict(os.environ, CAUSTIC_EDITOR_SCRIPT=script, CAUSTIC_EDITOR_HOME=os.path.join(tmp, "home"), **extra_env)
        run = xvfb_run([args.bin, scene_path], env, 3600, "1600x1000x24", tmp)
        if run.returncode != 0:
            sys.exit(f"editor_bench: the editor failed ({run.returncode}):\n{run.stderr[-2000:]}")
        with open(os.path.join(tmp, "report.json")) as f:
            return json.load(f)


def build_table(args):
    other = os.path.join(ROOT, "scenes", "dof.json")
    cold = {"MESA_SHADER_CACHE_DISABLE": "true", "CAUSTIC_PROGRAM_CACHE": "off"} if args.cold else {}
    print(f"scene {os.path.basename(args.scene)} at {args.size} x {args.size}, viewport scale {args.scale}, "
          f"{'cold (both caches off)' if args.cold else 'caches on'}")
    print(f"{'action':18} {'builds':22} {'longest frame after':>20} {'frames building':>16} {'to N spp':>10}")
    with scene_copy(args) as scene_file:
        for name, action, samples in BUILD_ACTIONS:
            text = BUILD_SCRIPT.format(scale=args.scale, samples=samples, action=action.format(hdr=args.hdr, other=other))
            if not args.cold:   # the caches warm for both rows, not only for the second
                run_session(args, scene_file, text, {})
            for label, background in (("on the window's thread", "0"), ("in the background", "1")):
                r = run_session(args, scene_file, text, dict(cold, CAUSTIC_BACKGROUND_BUILDS=background))
                print(f"{name:18} {label:22} {r['frame_ms_max_since_last_edit']:17.0f} ms {r['frames_building_shaders']:16d} "
                      f"{r['seconds_since_last_edit']:8.2f} s ({samples} spp)", flush=True)
    print(f"load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
