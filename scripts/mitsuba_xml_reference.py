#!/usr/bin/env python3
"""Renders a Mitsuba scene file with Mitsuba 3 itself: the reference kousen's Mitsuba loader
is checked against (crates/cpu/tests/mitsuba_reference.rs).

    pip install mitsuba numpy
    apt-get install libllvm19   # for the llvm variants (see scripts/mitsuba_reference.py)
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
    python3 scripts/mitsuba_xml_reference.py scenes/mitsuba/cornell-box.xml \\
        crates/render/tests/data/mitsuba-cornell-box-64.exr --res 64 --spp 16384

The file's `res` and `spp` defaults are set from the arguments, and any other of its defaults
by `--define NAME=VALUE` (`--define "spot=0, 0, 0"` for scenes/mitsuba/cornell-fog.xml's
reference); its own integrator, film and box filter are used. The samples are taken in passes of at most `--pass-spp`
each, seeded apart, and averaged (equal counts, so the mean is exact).
"""
import argparse
import time

import mitsuba as mi
import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("output", help="an .exr")
    ap.add_argument("--res", type=int, default=64)
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--pass-spp", type=int, default=1024)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--variant", default="llvm_ad_rgb", help="llvm_ad_rgb or scalar_rgb")
    ap.add_argument("--define", action="append", default=[], metavar="NAME=VALUE",
                    help="set one of the file's defaults (repeatable)")
    args = ap.parse_args()
    defines = dict(d.split("=", 1) for d in args.define)
    mi.set_variant(args.variant)
    per_pass = min(args.spp, args.pass_spp)
    if args.spp % per_pass:
        raise SystemExit("--spp must be a multiple of --pass-spp")
    scene = mi.load_file(args.scene, res=args.res, spp=per_pass, **defines)
    started = time.time()
    passes = args.spp // per_pass
    total = None
    for i in range(passes):
        image = np.array(mi.render(scene, seed=args.seed * 1_000_003 + i, spp=per_pass))
        total = image if total is None else total + image
    mean = total / passes
    mi.Bitmap(mean[:, :, :3].astype(np.float32)).write(args.output)
    print(f"{args.output}: {args.res}² at {args.spp} spp in {time.time() - started:.1f} s; "
          f"channel means {mean[:, :, :3].reshape(-1, 3).mean(axis=0)}")


if __name__ == "__main__":
    main()
