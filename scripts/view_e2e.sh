#!/usr/bin/env bash
# End-to-end check of `kousen view` (issue 5): open the shipped Cornell box in a window on a
# virtual X display (Xvfb) through whatever Vulkan adapter there is (lavapipe in CI), let it
# converge, and check that
#   1. the window really shows the image (a grab of the X screen is not blank where the window is),
#   2. the window's own screenshots show the box: block averages (the picture without its noise)
#      close to a `kousen render` of the same view,
#   3. the image converges: the later screenshot is closer to that reference than the earlier,
#   4. opening a broken file (the path a drag and drop takes, driven by --open-after) reports
#      the error and keeps the current scene; opening another scene shows that scene; opening
#      a sky map (.hdr) lights that scene as `kousen render --sky-map` does, and removing it
#      (--remove-sky-map-after, the overlay's button) shows the scene without it again,
#      the first scene, seen through a wide lens focused on its back wall, shows the blur that
#      `kousen render` with the same lens shows (its blocks' edges nearer to it than to the
#      pinhole's),
#   5. the window closes cleanly (exit 0) when asked to (--quit-after).
# Needs: xvfb (Xvfb), x11-apps (xwd), netpbm (xwdtopnm), python3; .ci/run installs them.
# Usage: scripts/view_e2e.sh [KOUSEN_BINARY]   (default target/debug/kousen, built if missing)
set -euo pipefail
cd "$(dirname "$0")/.."

kousen=${1:-target/debug/kousen}
[ -x "$kousen" ] || cargo build -p kousen --locked
scene=scenes/cornell-box.gltf
second=scenes/cornell-caustics.gltf
sky_map=scenes/skies/sunset.hdr
size=256
# A wide lens focused on the Cornell box's back wall: the blocks in front blur by 10 to 20 pixels.
lens="--aperture-radius 120 --focus-distance 1359"
work=$(mktemp -d)
trap 'kill "${xvfb_pid:-}" 2>/dev/null || true; [ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT

# A free display number and a virtual screen larger than the window.
display=99
while [ -e "/tmp/.X11-unix/X$display" ] || [ -e "/tmp/.X$display-lock" ]; do display=$((display + 1)); done
Xvfb ":$display" -screen 0 640x480x24 -nolisten tcp >"$work/xvfb.log" 2>&1 &
xvfb_pid=$!
for _ in $(seq 50); do [ -e "/tmp/.X11-unix/X$display" ] && break; sleep 0.1; done
export DISPLAY=":$display"
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$work}

echo "view_e2e: kousen view $scene on $DISPLAY"
printf '{"asset": {"version": "2.0"}, "nodes": [' >"$work/broken.gltf"
"$kousen" view "$scene" $lens --width $size --height $size --render-scale 1 --no-overlay \
    --screenshot-after 2 "$work/early.png" --screenshot-after 12 "$work/late.png" \
    --open-after 12.5 "$work/broken.gltf" --screenshot-after 14 "$work/kept.png" \
    --open-after 14.5 "$second" --screenshot-after 28 "$work/second.png" \
    --open-after 28.5 "$sky_map" --screenshot-after 42 "$work/sky.png" \
    --remove-sky-map-after 42.5 --screenshot-after 56 "$work/unlit.png" \
    --quit-after 57 >"$work/view.log" 2>&1 &
view_pid=$!

# Grab the whole X screen once the window has drawn for a while.
for _ in $(seq 600); do [ -e "$work/early.png" ] && break; kill -0 $view_pid 2>/dev/null || break; sleep 0.1; done
sleep 2
xwd -root -silent -display ":$display" | xwdtopnm >"$work/screen.ppm" 2>/dev/null || true

status=0
wait $view_pid || status=$?
cat "$work/view.log"
if [ $status -ne 0 ]; then
    echo "view_e2e: FAIL: kousen view exited with status $status" >&2
    exit 1
fi
for shot in early late kept second sky unlit; do
    [ -s "$work/$shot.png" ] || { echo "view_e2e: FAIL: no $shot screenshot" >&2; exit 1; }
done
grep -q "cannot open $work/broken.gltf" "$work/view.log" \
    || { echo "view_e2e: FAIL: the broken file's error was not reported" >&2; exit 1; }
grep -q "opened $sky_map" "$work/view.log" \
    || { echo "view_e2e: FAIL: the dropped sky map was not opened" >&2; exit 1; }
grep -q "removed the sky map from $second" "$work/view.log" \
    || { echo "view_e2e: FAIL: the sky map was not removed" >&2; exit 1; }

# References: the same scenes, camera and size rendered on the CPU backend. 128 passes leave
# their 8-pixel blocks' noise near 1 %, far below what the checks below tell apart.
reference_passes=128
"$kousen" render "$scene" $lens --backend cpu --width $size --height $size --passes $reference_passes -o "$work/reference.png"
"$kousen" render "$scene" --backend cpu --width $size --height $size --passes $reference_passes -o "$work/pinhole.png"
"$kousen" render "$second" --backend cpu --width $size --height $size --passes $reference_passes -o "$work/second-reference.png"
"$kousen" render "$second" --sky-map "$sky_map" --backend cpu --width $size --height $size --passes $reference_passes \
    -o "$work/sky-reference.png"
"$kousen" diff "$work/early.png" "$work/reference.png" --json "$work/early.json" >/dev/null
"$kousen" diff "$work/late.png" "$work/reference.png" --json "$work/late.json" >/dev/null
"$kousen" diff "$work/late.png" "$work/early.png" --json "$work/change.json" >/dev/null
for image in late kept second sky unlit reference pinhole second-reference sky-reference; do
    pngtopnm "$work/$image.png" >"$work/$image.ppm"
done

python3 - "$work" <<'PYTHON'
import json, sys

work = sys.argv[1]
early = json.load(open(f"{work}/early.json"))
late = json.load(open(f"{work}/late.json"))
change = json.load(open(f"{work}/change.json"))

def read_ppm(path):
    data = open(path, "rb").read()
    fields, pos = [], 0
    while len(fields) < 4:  # magic, width, height, maxval; skip comments
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos)
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    assert fields[0] == b"P6" and int(fields[3]) == 255, fields
    width, height = int(fields[1]), int(fields[2])
    return width, height, data[pos + 1:pos + 1 + width * height * 3]

def blocks(name, n=8):
    # n = 8 sees the picture's layout; n = 32 (8-pixel blocks) its edges' blur.
    """The picture without its noise: n x n blocks, mean 8-bit value per channel."""
    width, height, rgb = read_ppm(f"{work}/{name}.ppm")
    sums = [[0.0] * 3 for _ in range(n * n)]
    for y in range(height):
        for x in range(width):
            b = (y * n // height) * n + x * n // width
            for c in range(3):
                sums[b][c] += rgb[(y * width + x) * 3 + c]
    count = width * height / (n * n)
    return [[v / count for v in s] for s in sums]

def block_error(name, reference, n=8):
    """Mean absolute block difference relative to the reference's mean value."""
    a, b = blocks(name, n), blocks(reference, n)
    mean_value = sum(map(sum, b)) / (3 * len(b))
    return sum(abs(x - y) for s, r in zip(a, b) for x, y in zip(s, r)) / (3 * len(b)) / mean_value

failures = []
try:
    width, height, rgb = read_ppm(f"{work}/screen.ppm")
    lit = sum(1 for i in range(0, len(rgb), 3) if max(rgb[i:i + 3]) > 24)
    # The window is 256x256 on a black 640x480 screen: the box's walls light most of it.
    print(f"screen grab: {width}x{height}, {lit} pixels lit (window area {256 * 256})")
    if lit < 0.4 * 256 * 256:
        failures.append(f"the screen grab is (nearly) blank: {lit} lit pixels")
except Exception as e:
    failures.append(f"could not read the X screen grab: {e}")

print(f"early vs reference: rel_mse {early['rel_mse']:.4f}, mean_ratio {early['mean_ratio']:.3f}")
print(f"late  vs reference: rel_mse {late['rel_mse']:.4f}, mean_ratio {late['mean_ratio']:.3f}")
print(f"late  vs early:     rel_mse {change['rel_mse']:.5f}")
if not 0.8 < late["mean_ratio"] < 1.25:
    failures.append(f"the late screenshot's brightness is off: mean_ratio {late['mean_ratio']:.3f}")
for name in ("r", "g", "b"):
    ratio = late[f"mean_ratio_{name}"]
    if not 0.75 < ratio < 1.33:
        failures.append(f"the late screenshot's {name} channel is off: {ratio:.3f}")
if not change["rel_mse"] > 1e-5:
    failures.append("the image did not change between the screenshots")
if not late["rel_mse"] < early["rel_mse"]:
    failures.append("the image did not converge towards the reference")

shown = blocks("late")
left, right = shown[4 * 8 + 0], shown[4 * 8 + 7]  # the middle row's first and last blocks
print(f"left wall RGB {[round(v) for v in left]}, right wall {[round(v) for v in right]}")
if not (left[0] > 2 * left[1] and right[1] > 1.2 * right[0]):
    failures.append("the red wall is not on the left and the green one on the right")

errors = {
    "late vs its scene": block_error("late", "reference"),
    "kept (after the broken file) vs the first scene": block_error("kept", "reference"),
    "second vs the second scene": block_error("second", "second-reference"),
    "sky (the map dropped on the second scene) vs it rendered with --sky-map":
        block_error("sky", "sky-reference"),
    "unlit (the map removed again) vs the second scene": block_error("unlit", "second-reference"),
    "second vs the first scene": block_error("second", "reference"),
    "sky vs the second scene without the map": block_error("sky", "second-reference"),
    "unlit vs the second scene with the map": block_error("unlit", "sky-reference"),
}
lens_error = block_error("late", "reference", 32)
pinhole_error = block_error("late", "pinhole", 32)
lens_vs_pinhole = block_error("reference", "pinhole", 32)
print(f"8-pixel blocks, late vs its lens's render: {lens_error:.3f}, vs the pinhole's: "
      f"{pinhole_error:.3f} (the two renders differ by {lens_vs_pinhole:.3f})")
if not lens_error < 0.5 * pinhole_error:
    failures.append("the window does not show its lens's blur")
for what, error in errors.items():
    print(f"block error, {what}: {error:.3f}")
for what in list(errors)[:5]:
    if not errors[what] < 0.1:
        failures.append(f"block error {what} is {errors[what]:.3f} (must be < 0.1)")
if not errors["second vs the first scene"] > 2 * errors["second vs the second scene"]:
    failures.append("after opening the second scene the window does not show it")
if not errors["sky vs the second scene without the map"] > 2 * errors[list(errors)[3]]:
    failures.append("after dropping the sky map the window does not show it lit")
if not errors["unlit vs the second scene with the map"] > 2 * errors[list(errors)[4]]:
    failures.append("after removing the sky map the window still shows it lit")

for f in failures:
    print(f"view_e2e: FAIL: {f}", file=sys.stderr)
sys.exit(1 if failures else 0)
PYTHON
echo "view_e2e: ok"
