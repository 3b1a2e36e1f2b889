"""Mitsuba 3 side of `cargo xtask peer`: one JSON request per line on stdin, one JSON reply per
line on stdout (Mitsuba's own log goes to stderr).

Requests ({"cmd": ...}):
  hello                     versions of Mitsuba, Dr.Jit, NumPy and Python, the variants
  render                    variant, scene (XML path), threads, spp, seed, max_pass_spp, out
                            (EXR path or null): renders spp samples per pixel in passes of at
                            most max_pass_spp (seeds seed, seed + 1, ...), averages them and
                            reports the wall-clock seconds around the render calls and the
                            JIT compile time (Dr.Jit's kernel history: codegen + LLVM backend)
  microbench                variant, threads, lanes, repeats, alpha: GGX sample / eval / pdf
                            per second (see `microbench`)
  quit

Timing: `time.perf_counter()` around `mi.render` and `dr.eval` of the accumulated image (the
JIT variants are lazy: the work happens in `dr.eval`). Scene loading (and Mitsuba's BVH
build) is outside the timed region, as ggx's `--stats` excludes its BVH build. Images are
converted and written after the clock stops, with the thread count raised: after
`dr.set_thread_count(1)`, EXR I/O through `mi.Bitmap` deadlocks.
"""

import json
import os
import platform
import sys
import time
import traceback

import drjit as dr
import mitsuba as mi
import numpy as np

SCENES = {}


def set_variant(variant):
    """Switches Mitsuba's variant when it differs (loaded scenes are per variant)."""
    if mi.variant() != variant:
        mi.set_variant(variant)


def scene_of(variant, path):
    """The scene at `path` loaded in `variant`, cached."""
    key = (variant, path)
    if key not in SCENES:
        set_variant(variant)
        SCENES[key] = mi.load_file(path)
    return SCENES[key]


def is_jit(variant):
    """True for the LLVM and CUDA (JIT) variants."""
    return variant.startswith("llvm") or variant.startswith("cuda")


def jit_seconds(variant):
    """Seconds of JIT compilation (codegen + backend) since the history was last read."""
    if not is_jit(variant):
        return 0.0
    total = 0.0
    for k in dr.kernel_history():
        total += float(k.get("codegen_time", 0.0)) + float(k.get("backend_time", 0.0))
    return total / 1000.0


def write_exr(path, image, threads):
    """Writes `image` (H x W x 3 float32) as EXR with the thread count raised around it."""
    dr.set_thread_count(max(threads, os.cpu_count() or 2, 2))
    try:
        mi.Bitmap(image).write(path)
    finally:
        dr.set_thread_count(threads)


def render(req):
    """Renders one rung: passes of at most max_pass_spp, averaged; timed."""
    variant, threads = req["variant"], int(req["threads"])
    scene = scene_of(variant, req["scene"])
    set_variant(variant)
    dr.set_thread_count(threads)
    spp, seed = int(req["spp"]), int(req["seed"])
    per_pass = max(1, min(spp, int(req.get("max_pass_spp", spp))))
    if is_jit(variant):
        dr.set_flag(dr.JitFlag.KernelHistory, True)
        dr.kernel_history()  # reading it clears it
    passes = []
    left, i = spp, 0
    while left > 0:
        n = min(per_pass, left)
        passes.append((n, (seed + i) & 0xFFFFFFFF))
        left -= n
        i += 1
    start = time.perf_counter()
    acc = None
    for n, s in passes:
        img = mi.render(scene, spp=n, seed=s)
        term = img * (n / spp)
        acc = term if acc is None else acc + term
        dr.eval(acc)
    if is_jit(variant):
        dr.sync_thread()
    seconds = time.perf_counter() - start
    jit = jit_seconds(variant)
    image = np.array(acc, dtype=np.float32)[..., :3]
    if req.get("out"):
        write_exr(req["out"], image, threads)
    mean = image.reshape(-1, 3).mean(axis=0)
    return {
        "ok": True,
        "seconds": seconds,
        "jit_seconds": jit,
        "passes": len(passes),
        "width": int(image.shape[1]),
        "height": int(image.shape[0]),
        "mean": [float(x) for x in mean],
    }


def hemisphere(rng, n):
    """n cosine-distributed unit directions about +z (as ggx-core's bench inputs), 3 x n."""
    u1, u2 = rng.random(n, dtype=np.float32), rng.random(n, dtype=np.float32)
    r, phi = np.sqrt(u1), 2.0 * np.pi * u2
    return np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(0.0, 1.0 - u1))]).astype(np.float32)


def best_rate(fn, lanes, repeats, variant):
    """Lanes per second of fn (best of `repeats`, after one warm-up call that compiles)."""
    fn()
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        if is_jit(variant):
            dr.sync_thread()
        best = min(best, time.perf_counter() - start)
    return lanes / best


def microbench(req):
    """GGX throughput on `lanes` lanes at alpha `alpha` (F = 1, as ggx-core's bench):
    the distribution's D(m), visible-normal sample (m, pdf), visible-normal sample then
    reflection (the reflected direction, ggx-core's batch::sample_vndf), and the
    roughconductor BSDF's eval, pdf and sample (with its weight)."""
    variant, threads = req["variant"], int(req["threads"])
    lanes, repeats, alpha = int(req["lanes"]), int(req["repeats"]), float(req["alpha"])
    set_variant(variant)
    dr.set_thread_count(threads)
    if not is_jit(variant):
        raise ValueError("the micro-benchmark needs a JIT variant (vectorized over lanes)")
    rng = np.random.default_rng(7)
    wo_np, wi_np, wm_np = hemisphere(rng, lanes), hemisphere(rng, lanes), hemisphere(rng, lanes)
    u_np = rng.random((2, lanes), dtype=np.float32)
    wo, wi, wm = mi.Vector3f(wo_np), mi.Vector3f(wi_np), mi.Vector3f(wm_np)
    u, u1 = mi.Point2f(u_np), mi.Float(u_np[0])
    dr.eval(wo, wi, wm, u, u1)
    dr.sync_thread()
    distr = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, alpha, alpha, True)
    bsdf = mi.load_dict({
        "type": "roughconductor", "distribution": "ggx", "sample_visible": True,
        "alpha": alpha, "material": "none",
    })
    ctx = mi.BSDFContext()
    si = dr.zeros(mi.SurfaceInteraction3f, lanes)
    si.wi = wo
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    dr.eval(si)
    dr.sync_thread()

    def d():
        dr.eval(distr.eval(wm))

    def sample_wm():
        m, pdf = distr.sample(wo, u)
        dr.eval(m, pdf)

    def sample_reflect():
        m, pdf = distr.sample(wo, u)
        r = mi.reflect(wo, m)
        dr.eval(r, pdf)

    def eval_():
        dr.eval(bsdf.eval(ctx, si, wi))

    def pdf():
        dr.eval(bsdf.pdf(ctx, si, wi))

    def sample():
        bs, weight = bsdf.sample(ctx, si, u1, u)
        dr.eval(bs.wo, bs.pdf, weight)

    ops = [("D", d), ("sample_wm_vndf", sample_wm), ("sample_reflect", sample_reflect),
           ("eval", eval_), ("pdf", pdf), ("sample", sample)]
    rates = {name: best_rate(fn, lanes, repeats, variant) for name, fn in ops}
    return {"ok": True, "per_second": rates, "lanes": lanes, "threads": threads}


def hello(_req):
    """Versions and variants."""
    return {
        "ok": True,
        "mitsuba": mi.__version__,
        "drjit": dr.__version__,
        "numpy": np.__version__,
        "python": platform.python_version(),
        "variants": list(mi.variants()),
    }


def main():
    """The request loop."""
    mi.set_log_level(mi.LogLevel.Warn)
    handlers = {"hello": hello, "render": render, "microbench": microbench}
    for line in sys.stdin:
        line = line.strip()
        if not line:
            continue
        try:
            req = json.loads(line)
            if req.get("cmd") == "quit":
                print(json.dumps({"ok": True}), flush=True)
                return
            reply = handlers[req["cmd"]](req)
        except Exception as e:  # reported to xtask, which fails with it
            reply = {"ok": False, "error": f"{type(e).__name__}: {e}", "traceback": traceback.format_exc()}
        print(json.dumps(reply), flush=True)


if __name__ == "__main__":
    mi.set_variant("scalar_rgb")
    main()
