"""The body of every farm task: run caustic once, in a fresh folder, and hand back the files it
wrote (their bytes travel through Ray's object store, so outputs need no shared file system)."""

import os
import subprocess
import tempfile
import time


class CausticFailed(RuntimeError):
    """caustic exited non-zero: a bad scene or flag, which a retry would not mend."""


def _hold(spec):
    # A test hook (docs/farm.md): with $CAUSTIC_FARM_HOLD_DIR set by the driver, a task whose
    # <name>.hold file exists there removes it, writes its pid to <name>.pid and waits to be
    # killed, so a test can kill a worker in the middle of a task (the retry finds no .hold).
    hold_dir = spec.get("hold_dir")
    if not hold_dir:
        return
    hold = os.path.join(hold_dir, spec["name"] + ".hold")
    try:
        os.remove(hold)
    except FileNotFoundError:
        return
    with open(os.path.join(hold_dir, spec["name"] + ".pid.tmp"), "w") as f:
        f.write(str(os.getpid()))
    os.replace(os.path.join(hold_dir, spec["name"] + ".pid.tmp"), os.path.join(hold_dir, spec["name"] + ".pid"))
    while True:
        time.sleep(3600)


def run_caustic(spec, gpu_ids=()):
    """spec: {"caustic": program, "args": [...], "name": label, "cwd": folder or None,
    "env": {...}, "hold_dir": test hook}. Returns {"files": {name: bytes}, "stderr", "seconds"}."""
    _hold(spec)
    env = dict(os.environ)
    env.update(spec.get("env", {}))
    args = list(spec["args"])
    if gpu_ids:
        # Ray numbers GPUs as the machine does and limits CUDA_VISIBLE_DEVICES to the task's;
        # caustic picks the EGL device by its CUDA number, in the machine's numbering, so the
        # variable is cleared for it and the number passed (renderer/gl_context.h).
        env.pop("CUDA_VISIBLE_DEVICES", None)
        args += ["--gpu", str(int(gpu_ids[0]))]
    start = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="caustic-farm-") as out:
        p = subprocess.run([spec["caustic"], *args, "--output", out], capture_output=True, text=True,
                           env=env, cwd=spec.get("cwd") or None)
        if p.returncode != 0:
            raise CausticFailed("%s: caustic exited with %d:\n%s" % (spec["name"], p.returncode, p.stderr.strip()))
        files = {}
        for line in p.stdout.splitlines():
            path = line.strip()
            if path:
                with open(path, "rb") as f:
                    files[os.path.basename(path)] = f.read()
    return {"files": files, "stderr": p.stderr, "seconds": time.monotonic() - start}


def task_entry(spec):
    """What a Ray task runs (cli.py wraps it with ray.remote): run_caustic with the GPU Ray gave
    the task, and the node it ran on."""
    import ray

    out = run_caustic(spec, ray.get_gpu_ids())
    out["node"] = ray.get_runtime_context().get_node_id()
    return out
