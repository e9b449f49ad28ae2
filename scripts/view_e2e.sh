#!/usr/bin/env bash
# End-to-end check of `kousen view` (issue 5): open the shipped Cornell box in a window on a
# virtual X display (Xvfb) through whatever Vulkan adapter there is (lavapipe in CI), let it
# converge, and check that
#   1. the window really shows the image (a grab of the X screen is not blank where the window is),
#   2. the window's own screenshots show the box: block averages (the picture without its noise)
#      close to a `kousen render` of the same view,
#   3. the image converges: the later screenshot is closer to that reference than the earlier,
#   4. the window closes cleanly (exit 0) when asked to (--quit-after).
# Needs: xvfb (Xvfb), x11-apps (xwd), netpbm (xwdtopnm), python3; .ci/run installs them.
# Usage: scripts/view_e2e.sh [KOUSEN_BINARY]   (default target/debug/kousen, built if missing)
set -euo pipefail
cd "$(dirname "$0")/.."

kousen=${1:-target/debug/kousen}
[ -x "$kousen" ] || cargo build -p kousen --locked
scene=scenes/cornell-box.gltf
size=256
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
DISPLAY=":$display" "$kousen" view "$scene" --width $size --height $size --render-scale 1 \
    --no-overlay --screenshot-after 2 "$work/early.png" --screenshot-after 12 "$work/late.png" \
    --quit-after 14 >"$work/view.log" 2>&1 &
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
for shot in early late; do
    [ -s "$work/$shot.png" ] || { echo "view_e2e: FAIL: no $shot screenshot" >&2; exit 1; }
done

# The reference: the same scene, camera and size rendered to convergence on the CPU backend.
"$kousen" render "$scene" --backend cpu --width $size --height $size --passes 256 -o "$work/reference.png"
"$kousen" diff "$work/early.png" "$work/reference.png" --json "$work/early.json" >/dev/null
"$kousen" diff "$work/late.png" "$work/reference.png" --json "$work/late.json" >/dev/null
"$kousen" diff "$work/late.png" "$work/early.png" --json "$work/change.json" >/dev/null
for image in late reference; do pngtopnm "$work/$image.png" >"$work/$image.ppm"; done

python3 - "$work" <<'EOF'
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

failures = []
try:
    width, height, rgb = read_ppm(f"{work}/screen.ppm")
    lit = sum(1 for i in range(0, len(rgb), 3) if max(rgb[i:i + 3]) > 24)
    # The window is 256x256 on a black 640x480 screen: the box's walls light most of it.
    print(f"screen grab: {width}x{height}, {lit} pixels lit (window area {256 * 256})")
    if lit < 0.4 * 256 * 256:
        failures.append(f"the screen grab is (nearly) blank: {lit} lit pixels")
except Exception as e:  # no grab: say so, the window's own screenshots still count
    failures.append(f"could not read the X screen grab: {e}")

print(f"early vs reference: rel_mse {early['rel_mse']:.4f}, mean_ratio {early['mean_ratio']:.3f}")
print(f"late  vs reference: rel_mse {late['rel_mse']:.4f}, mean_ratio {late['mean_ratio']:.3f}")
print(f"late  vs early:     rel_mse {change['rel_mse']:.5f}")
if not 0.8 < late["mean_ratio"] < 1.25:
    failures.append(f"the late screenshot's brightness is off: mean_ratio {late['mean_ratio']:.3f}")
for name in ("r", "g", "b"):  # the red and green walls: every channel in proportion
    ratio = late[f"mean_ratio_{name}"]
    if not 0.75 < ratio < 1.33:
        failures.append(f"the late screenshot's {name} channel is off: {ratio:.3f}")
# The picture without its noise: 8x8 blocks of 32x32 pixels, mean 8-bit value per channel.
def blocks(path, n=8):
    width, height, rgb = read_ppm(path)
    sums = [[0.0] * 3 for _ in range(n * n)]
    for y in range(height):
        for x in range(width):
            b = (y * n // height) * n + x * n // width
            for c in range(3):
                sums[b][c] += rgb[(y * width + x) * 3 + c]
    count = width * height / (n * n)
    return [[v / count for v in s] for s in sums]

shown, reference = blocks(f"{work}/late.ppm"), blocks(f"{work}/reference.ppm")
# Mean absolute difference of block values, relative to the reference's mean value.
mean_value = sum(map(sum, reference)) / (3 * len(reference))
block_error = sum(abs(a - b) for s, r in zip(shown, reference) for a, b in zip(s, r)) / (3 * len(reference)) / mean_value
left, right = shown[4 * 8 + 0], shown[4 * 8 + 7]  # the middle row's first and last blocks
print(f"block error {block_error:.3f}; left wall RGB {[round(v) for v in left]}, right wall {[round(v) for v in right]}")
if not block_error < 0.1:
    failures.append(f"the late screenshot does not look like the reference: block error {block_error:.3f}")
if not (left[0] > 2 * left[1] and right[1] > 1.2 * right[0]):
    failures.append("the red wall is not on the left and the green one on the right")
if not change["rel_mse"] > 1e-5:
    failures.append("the image did not change between the screenshots")
if not late["rel_mse"] < early["rel_mse"]:
    failures.append("the image did not converge towards the reference")
for f in failures:
    print(f"view_e2e: FAIL: {f}", file=sys.stderr)
sys.exit(1 if failures else 0)
EOF
echo "view_e2e: ok"
