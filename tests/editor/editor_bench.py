#!/usr/bin/env python3
"""The editor's responsiveness benchmark (not a test): runs the real editor under xvfb-run on a
scene at a given resolution with a scripted session (converge a little, a 20-frame gizmo drag, a
translate, an orbit, each followed by rendering) and prints the script's report: frame times
while rendering (median, p95, max), all frames, and the time from each edit to the first frame
that shows it. Figures go to docs/performance.md with the machine and its load.

    tests/editor/editor_bench.py [--size N] [--scene FILE] [--bin build/caustic]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "cornell-box.json"))
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "caustic"))
    args = ap.parse_args()
    with open(args.scene) as f:
        scene = json.load(f)
    scene.setdefault("render", {})["width"] = args.size
    scene["render"]["height"] = args.size
    with tempfile.TemporaryDirectory(prefix="caustic-editor-bench-") as tmp:
        # Relative file names in the scene stay valid: write the copy beside the original.
        scene_file = os.path.join(os.path.dirname(os.path.abspath(args.scene)), f".editor-bench-{os.getpid()}.json")
        with open(scene_file, "w") as f:
            json.dump(scene, f)
        script = os.path.join(tmp, "script.txt")
        with open(script, "w") as f:
            f.write(SCRIPT)
        env = dict(os.environ, CAUSTIC_EDITOR_SCRIPT=script, CAUSTIC_EDITOR_HOME=os.path.join(tmp, "home"))
        try:
            run = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1600x1000x24", args.bin, scene_file],
                                 env=env, capture_output=True, text=True, timeout=900)
        finally:
            os.remove(scene_file)
        if run.returncode != 0:
            sys.exit(f"editor_bench: the editor failed ({run.returncode}):\n{run.stderr[-2000:]}")
        with open(os.path.join(tmp, "report.json")) as f:
            report = json.load(f)
    keys = ["width", "height", "rendering_frames", "frame_ms_median", "frame_ms_p95", "frame_ms_max",
            "all_frames_ms_median", "frame_overhead_ms_median", "samples_per_frame_mean", "edit_to_frame_ms_median", "edit_to_frame_ms"]
    for k in keys:
        print(f"{k:24} {report.get(k)}")


if __name__ == "__main__":
    main()
