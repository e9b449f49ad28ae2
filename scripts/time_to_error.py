#!/usr/bin/env python3
"""Time to a given error: kousen configurations against Mitsuba 3's path tracer, one run.

Renders the scene with each kousen configuration for each time budget and with Mitsuba at each
sample count, measures every image against a converged reference over the whole image and
inside a window (`kousen diff`, `--window`), and reports, for each kousen configuration, how
long it takes to reach the error Mitsuba reaches with its largest sample count (log-log
interpolation between the two budgets around it). Everything runs in turn on this machine, so
the times compare. Needs Mitsuba (scripts/mitsuba_reference.py says how to install it).

    python3 scripts/time_to_error.py --kousen target/release/kousen \\
        --scene scenes/cornell-caustics.gltf \\
        --reference docs/reference/cornell-caustics-mitsuba-128.exr --width 128 \\
        --window 74,106,24,16 --times 2,4,8,16 --mitsuba-spp 64,256,1024 \\
        --config "stochastic=--backend cpu --eye-every 1" \\
        --config "full=--backend cpu --eye-every 1 --density full" \\
        --json docs/bench/time-to-error.json
"""

import argparse
import json
import math
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time


def diff(kousen, image, reference, window=None):
    """relMSE of image against reference, over the whole image or a window."""
    cmd = [kousen, "diff", image, reference]
    if window:
        cmd += ["--window", window]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    figures = dict(line.split(" ", 1) for line in out.splitlines())
    return float(figures["rel_mse"])


def time_to_reach(points, target):
    """Seconds at which the error falls to target, log-log interpolated between the measured
    (seconds, error) points; (seconds, how) with how "interpolated" or "extrapolated"."""
    points = sorted(points)
    for (t0, e0), (t1, e1) in zip(points, points[1:]):
        if e0 >= target >= e1 and e0 > e1:
            slope = (math.log(t1) - math.log(t0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + slope * (math.log(target) - math.log(e0))), "interpolated"
    (t0, e0), (t1, e1) = (points[0], points[1]) if target > points[0][1] else (points[-2], points[-1])
    if e0 <= e1:
        return float("nan"), "error does not fall"
    slope = (math.log(t1) - math.log(t0)) / (math.log(e1) - math.log(e0))
    return math.exp(math.log(t0) + slope * (math.log(target) - math.log(e0))), "extrapolated"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--kousen", default="target/release/kousen")
    ap.add_argument("--scene", required=True)
    ap.add_argument("--reference", required=True)
    ap.add_argument("--width", type=int, required=True)
    ap.add_argument("--window", required=True, help="X,Y,W,H, as kousen diff --window takes it")
    ap.add_argument("--times", default="2,4,8,16", help="kousen --time budgets, seconds")
    ap.add_argument("--mitsuba-spp", default="64,256,1024")
    ap.add_argument("--config", action="append", required=True,
                    help="NAME=kousen render arguments (may be given several times)")
    ap.add_argument("--seed", type=int, default=7, help="Mitsuba's seed")
    ap.add_argument("--mitsuba-args", default="",
                    help="more arguments for mitsuba_reference.py (e.g. \"--exterior "
                         "marble=water\")")
    ap.add_argument("--seeds", default="7",
                    help="kousen's seeds: each budget is rendered once per seed and its error is "
                         "the mean over them (one seed's error moves ~15 %% between seeds)")
    ap.add_argument("--json")
    args = ap.parse_args()
    log = lambda s: print(s, file=sys.stderr, flush=True)
    here = os.path.dirname(os.path.abspath(__file__))
    rows = []
    seeds = [int(x) for x in args.seeds.split(",")]
    with tempfile.TemporaryDirectory() as tmp:
        for spp in [int(s) for s in args.mitsuba_spp.split(",")]:
            out = os.path.join(tmp, "mitsuba-%d.exr" % spp)
            run = subprocess.run(
                [sys.executable, os.path.join(here, "mitsuba_reference.py"), args.scene, out,
                 "--width", str(args.width), "--spp", str(spp), "--seed", str(args.seed)]
                + shlex.split(args.mitsuba_args),
                check=True, capture_output=True, text=True)
            # The script's own render loop time (scene loading and the first JIT included).
            seconds = float(re.findall(r"spp in \d+ passes, ([0-9.]+) s", run.stderr)[-1])
            # `volpath` where the scene has absorbing media (the script says so), else `path`.
            integrator = "volpath" if "volpath" in run.stderr + run.stdout else "path"
            rows.append({"renderer": "mitsuba", "config": integrator, "budget": "%d spp" % spp,
                         "seconds": seconds})
            rows[-1]["image"] = out
            log("mitsuba %d spp: %.2f s" % (spp, seconds))
        for config in args.config:
            name, extra = config.split("=", 1)
            for budget in [float(t) for t in args.times.split(",")]:
                for seed in seeds:
                    out = os.path.join(tmp, "kousen-%s-%g-%d.pfm" % (name, budget, seed))
                    stats = out + ".json"
                    subprocess.run(
                        [args.kousen, "render", args.scene, "-o", out, "--width", str(args.width),
                         "--time", str(budget), "--seed", str(seed), "--stats", stats]
                        + shlex.split(extra), check=True, capture_output=True)
                    with open(stats) as f:
                        st = json.load(f)
                    rows.append({"renderer": "kousen", "config": name, "arguments": extra,
                                 "budget": "%d passes" % st["passes"], "seconds": st["seconds"],
                                 "seed": seed, "photon_slots": st["photon_slots"],
                                 "eye_every": st.get("eye_every"), "density": st.get("density"),
                                 "time_budget": budget, "image": out})
                    log("kousen %s %g s seed %d: %d passes" % (name, budget, seed, st["passes"]))
        for row in rows:
            row["rel_mse_whole"] = diff(args.kousen, row["image"], args.reference)
            row["rel_mse_window"] = diff(args.kousen, row["image"], args.reference, args.window)
            del row["image"]

    mitsuba = [r for r in rows if r["renderer"] == "mitsuba"]
    last = max(mitsuba, key=lambda r: r["seconds"])
    summary = []
    for name in dict.fromkeys(r["config"] for r in rows if r["renderer"] == "kousen"):
        own = [r for r in rows if r["config"] == name]
        budgets = {}
        for r in own:
            budgets.setdefault(r["time_budget"], []).append(r)
        means = [{key: sum(r[key] for r in group) / len(group)
                  for key in ["seconds", "rel_mse_whole", "rel_mse_window"]}
                 for group in budgets.values()]
        entry = {"config": name, "seeds": len(own) // max(len(budgets), 1),
                 "mean_per_budget": means}
        for region in ["whole", "window"]:
            target = last["rel_mse_" + region]
            seconds, how = time_to_reach([(m["seconds"], m["rel_mse_" + region]) for m in means],
                                         target)
            entry[region] = {"target_rel_mse": target, "mitsuba_seconds": last["seconds"],
                             "kousen_seconds": seconds, "how": how,
                             "speedup": last["seconds"] / seconds}
        summary.append(entry)

    print("%-8s %-12s %-12s %8s %12s %12s" % ("renderer", "config", "budget", "seconds",
                                               "relMSE whole", "relMSE window"))
    for r in rows:
        print("%-8s %-12s %-12s %8.2f %12.5f %12.5f" % (r["renderer"], r["config"], r["budget"],
              r["seconds"], r["rel_mse_whole"], r["rel_mse_window"]))
    print()
    for s in summary:
        for m in s["mean_per_budget"]:
            print("%-12s mean of %d seeds: %8.2f s %12.5f %12.5f" % (
                s["config"], s["seeds"], m["seconds"], m["rel_mse_whole"], m["rel_mse_window"]))
    for s in summary:
        for region in ["whole", "window"]:
            e = s[region]
            print("%-12s %-6s reaches Mitsuba's %.5f (%.2f s) in %.2f s (%s): %.2fx" % (
                s["config"], region, e["target_rel_mse"], e["mitsuba_seconds"],
                e["kousen_seconds"], e["how"], e["speedup"]))
    if args.json:
        report = {"scene": args.scene, "reference": args.reference, "width": args.width,
                  "window": args.window, "date": time.strftime("%Y-%m-%d"),
                  "rows": rows, "summary": summary}
        with open(args.json, "w") as f:
            json.dump(report, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
