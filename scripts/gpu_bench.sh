#!/bin/bash
# Every figure the issues ask of a real GPU, in one call of the `device` tool
# (/work/.library/device), so that a session lent a GPU spends its few device minutes measuring.
#
#   scripts/gpu_bench.sh pack            # here: release binary, shared scenes, Vulkan loader
#   device run, carry [".gl", ".device"]:  bash scripts/gpu_bench.sh run [all|traversal|render|density]
#
# `pack` fills two git-ignored folders that travel with the call: `.device/` (the stripped
# release binary and the shared scenes, compressed: `../shared` beside the checkout does not
# travel) and `.gl/` (the Vulkan loader's Debian package, as the device README says).
# `run` unpacks them on the device machine, writes every JSON, image and log and packs them
# into $OUT/results.tar.gz (the tool brings back at most 8 files), and prints a short summary
# last. `all` takes about 5 minutes on an H200 machine (16 cores);
# `traversal` and `render` split it in two calls if one runs long. `density` (not in `all`,
# about 3 minutes) compares the GPU's estimators at equal time in murky glass: the stochastic
# hash (the GPU default) against full lists, each against a longer full-lists render
# (docs/BENCHMARKS.md §3, session 43: which one a GPU should default to there).
#
# Locally (no $OUT), `run` writes under out/gpu-bench and uses lavapipe: a dry run of the whole
# thing, with KOUSEN_BENCH_QUICK=1 for small sizes.
set -euo pipefail

here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
stage=${2:-all}

pack() {
    cargo build --release --locked -p kousen
    mkdir -p .device
    strip -o .device/kousen target/release/kousen
    local shared=${SHARED_SCENES:-../shared/scenes}
    tar -C "$shared" -cJf .device/scenes.tar.xz bunny/bunny.obj cornell-metal \
        crytek-sponza sponza-dabrovic/sponza.obj
    if ! ls .gl/*.deb >/dev/null 2>&1; then
        mkdir -p .gl /tmp/amd64/partial
        local o=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64)
        apt-get "${o[@]}" update >/dev/null
        (cd .gl && apt-get "${o[@]}" download libvulkan1)
    fi
    du -ch .device .gl | tail -n 1
}

# The Vulkan loader, and the NVIDIA driver's manifest where the machine has one.
vulkan() {
    if ls .gl/*.deb >/dev/null 2>&1 && ! ldconfig -p | grep -q libvulkan; then
        for f in .gl/*.deb; do dpkg -x "$f" /; done
        ldconfig
    fi
    local icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
    if [ -f "$icd" ]; then
        export VK_DRIVER_FILES=$icd
    fi
}

run() {
    # The results stay outside $OUT but for the archive: the tool brings back at most 8 files.
    local work=$here/out/gpu-bench
    [ -n "${OUT:-}" ] && work=/tmp/kousen-bench
    local results=$work/results
    mkdir -p "$results"
    local kousen=$here/.device/kousen
    [ -x "$kousen" ] || kousen=$here/target/release/kousen
    vulkan
    local scenes=/tmp/kousen-scenes
    mkdir -p "$scenes"
    if [ -f .device/scenes.tar.xz ]; then
        tar -C "$scenes" -xJf .device/scenes.tar.xz
    else
        scenes=$(cd "${SHARED_SCENES:-../shared/scenes}" && pwd)
    fi
    local lit=/tmp/kousen-sponza-lit
    sh scripts/lit_sponza.sh "$scenes" "$lit"

    # Sizes: the issues' own, or small ones for a dry run on lavapipe.
    local size=1024 slots=1048576 caustic_time=20 sponza_time=30 metal_time=60 runs=5
    local murky_time=20 murky_reference_time=120
    if [ -n "${KOUSEN_BENCH_QUICK:-}" ]; then
        size=128 slots=16384 caustic_time=2 sponza_time=3 metal_time=3
        murky_time=2 murky_reference_time=4
    fi
    {
        date -u
        uname -a
        nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,memory.total \
            --format=csv 2>&1 || true
        nproc
    } >"$results/machine.txt"

    local log=$results/log.txt
    : >"$log"
    step() {
        echo "== $*" | tee -a "$log"
        local start=$SECONDS
        "$@" >>"$log" 2>&1 || echo "!! failed ($?): $*" | tee -a "$log"
        echo "   $((SECONDS - start)) s" | tee -a "$log"
    }

    if [ "$stage" = all ] || [ "$stage" = traversal ]; then
        step "$kousen" bench traversal "$scenes/bunny/bunny.obj" \
            "$scenes/cornell-metal/cornell_metal.obj" --view outside --size "$size" \
            --runs "$runs" --json "$results/traversal-outside.json"
        step "$kousen" bench traversal "$scenes/crytek-sponza/sponza.obj" \
            "$scenes/sponza-dabrovic/sponza.obj" --view inside --size "$size" \
            --runs "$runs" --json "$results/traversal-inside.json"
        # The scene in textures too (the default on CPU-type adapters only): measured on a GPU,
        # it decides whether GPUs should read the scene from texels as well.
        step "$kousen" bench traversal "$scenes/bunny/bunny.obj" \
            "$scenes/cornell-metal/cornell_metal.obj" --view outside --size "$size" \
            --runs "$runs" --devices gpu --scene-storage texels \
            --json "$results/traversal-outside-texels.json"
        step "$kousen" bench traversal "$scenes/crytek-sponza/sponza.obj" \
            "$scenes/sponza-dabrovic/sponza.obj" --view inside --size "$size" \
            --runs "$runs" --devices gpu --scene-storage texels \
            --json "$results/traversal-inside-texels.json"
    fi
    if [ "$stage" = all ] || [ "$stage" = render ]; then
        step "$kousen" bench photons scenes/cornell-caustics.gltf "$lit/sponza.obj" \
            --photons "$slots" --runs "$runs" --json "$results/photons.json"
        # The talk's ~100 M paths per minute on a GTX 680; host CPU time; memory by buffer.
        step "$kousen" render scenes/cornell-caustics.gltf -o "$results/cornell-caustics.png" \
            --width 512 --height 512 --time "$caustic_time" --backend gpu \
            --stats "$results/render-cornell-caustics.json"
        step "$kousen" render "$lit/sponza.obj" -o "$results/sponza.png" \
            --eye=900,150,0 --target=-900,400,0 --fov 75 --width 1920 --height 1080 \
            --photons 1048576 --time "$sponza_time" --backend gpu \
            --stats "$results/render-sponza-1080.json"
        # glslppm's settings (../shared/scenes/cornell-metal/README.md).
        step "$kousen" render "$scenes/cornell-metal/cornell-metal.gltf" \
            -o "$results/cornell-metal.pfm" --width 512 --height 512 --photons 262144 \
            --eye-every 10 --alpha 0.7 --hash-ratio 1 --max-depth 10 --time "$metal_time" \
            --backend gpu --stats "$results/render-cornell-metal.json"
    fi
    if [ "$stage" = density ]; then
        local murky=(scenes/cornell-murky.gltf --width 512 --height 512 --backend gpu)
        step "$kousen" render "${murky[@]}" -o "$results/murky-reference.pfm" --density full \
            --seed 99 --time "$murky_reference_time" --stats "$results/render-murky-reference.json"
        for density in stochastic full; do
            step "$kousen" render "${murky[@]}" -o "$results/murky-$density.pfm" \
                --density "$density" --seed 1 --time "$murky_time" \
                --stats "$results/render-murky-$density.json"
            step "$kousen" diff "$results/murky-$density.pfm" "$results/murky-reference.pfm" \
                --window 120,328,128,96 --json "$results/diff-murky-$density-ball.json"
            step "$kousen" diff "$results/murky-$density.pfm" "$results/murky-reference.pfm" \
                --json "$results/diff-murky-$density.json"
        done
    fi
    tar -C "$work" -czf "${OUT:-$work}/results.tar.gz" results
    summary "$results"
}

# The lines worth reading in the reply: Mrays/s per variant, paths per second and minute,
# host CPU share and memory.
summary() {
    local results=$1
    cat "$results/machine.txt"
    grep -E "^(==|!!)" "$results/log.txt" || true
    python3 - "$results" <<'EOF'
import glob, json, os, sys
results = sys.argv[1]
for path in sorted(glob.glob(os.path.join(results, "traversal-*.json"))):
    data = json.load(open(path))
    print(os.path.basename(path), data["adapter"]["name"], "| scene in",
          data.get("scene_storage"), "| cpu:", data.get("cpu_model"))
    rows = {}
    for r in data["results"]:
        scene = "/".join(r["path"].split("/")[-2:])
        row = rows.setdefault((scene, r["rays"]), {"mismatches": 0})
        row[(r["device"], r["variant"])] = r["mrays_per_s"]
        row["mismatches"] += r["mismatches"]
    variants = ["stack", "tbvh", "mtbvh", "mtbvh16", "mtbvh4"]
    print("  Mrays/s %-22s" % "", " ".join("%8s" % v for v in variants), "| same on cpu")
    for (scene, rays), row in rows.items():
        cell = lambda d, v: "%8.2f" % row[(d, v)] if (d, v) in row else "%8s" % "-"
        print("  %-28s %-8s" % (scene, rays), " ".join(cell("gpu", v) for v in variants), "|",
              " ".join(cell("cpu", v) for v in variants), "| mismatches", row["mismatches"])
path = os.path.join(results, "photons.json")
if os.path.exists(path):
    data = json.load(open(path))
    print("photons.json", data["adapter"]["name"], "| %d slots" % data["photon_slots"])
    for r in data["results"]:
        print("  %-18s %-4s %-6s %8.3f Mpaths/s %9.1f Mpaths/min" % (
            r["scene"], r["device"], r["scheme"], r["photon_paths_per_s"] * 1e-6,
            r["photon_paths_per_min"] * 1e-6))
for path in sorted(glob.glob(os.path.join(results, "diff-*.json"))):
    d = json.load(open(path))
    print("%s: relMSE %.3g, mean ratio %.4f" % (os.path.basename(path), d["rel_mse"], d["mean_ratio"]))
for path in sorted(glob.glob(os.path.join(results, "render-*.json"))):
    s = json.load(open(path))
    mem = sum(s.get("memory_bytes", {}).values())
    print("%s: %s, %d passes, %.3g paths/s = %.3g G/min, host CPU %.2f %% of %.1f s, %.1f MiB" % (
        os.path.basename(path), s["adapter"], s["passes"], s["photon_paths_per_second"],
        s["photon_paths_per_second"] * 60e-9, 100 * s["host_cpu_seconds"] / s["seconds"],
        s["seconds"], mem / 2**20))
EOF
}

case "${1:-}" in
pack) pack ;;
run) run ;;
*)
    echo "usage: scripts/gpu_bench.sh pack | run [all|traversal|render|density]" >&2
    exit 2
    ;;
esac
