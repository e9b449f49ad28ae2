#!/usr/bin/env python3
"""Noise of a flat back-wall patch of cornell-metal: kousen's linear render against glslppm's PNG.

    python3 scripts/glslppm_noise.py KOUSEN.exr|.pfm ../shared/scenes/cornell-metal/glslppm-60s.png

Needs numpy, pillow and OpenEXR-free reading: kousen writes .pfm, which this reads itself (render
with `-o out.pfm`). glslppm's PNG is undone to relative linear radiance: sRGB decode, then the
inverse of its display map 1 − exp(−k·L) (ANCHORS: k = 60000 × 0.627); the scale does not matter
because the figure is relative. Noise = standard deviation of (patch − its 5×5 box blur) divided
by the patch's mean, so shading gradients and absolute brightness drop out.
"""
import sys

import numpy as np
from PIL import Image

# The back wall right of the tall box, below the ceiling's shadow edge (x0, y0, x1, y1).
PATCH = (280, 130, 380, 210)
DISPLAY_K = 60000.0 * 0.627


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    channels = 3 if kind == b"PF" else 1
    image = data.reshape(height, width, channels)[::-1]
    return image.mean(axis=2)


def read_glslppm(path):
    v = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0
    linear = np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)
    linear = np.clip(linear, 0.0, 1.0 - 1e-6)
    return (-np.log1p(-linear) / DISPLAY_K).mean(axis=2)


def relative_noise(luminance):
    x0, y0, x1, y1 = PATCH
    patch = luminance[y0 - 2 : y1 + 2, x0 - 2 : x1 + 2]
    kernel = np.ones(5) / 5.0
    blurred = np.apply_along_axis(lambda r: np.convolve(r, kernel, "valid"), 1, patch)
    blurred = np.apply_along_axis(lambda c: np.convolve(c, kernel, "valid"), 0, blurred)
    centre = patch[2:-2, 2:-2]
    return float(np.std(centre - blurred) / np.mean(centre)), float(np.mean(centre))


def main():
    ours, theirs = sys.argv[1], sys.argv[2]
    noise_ours, mean_ours = relative_noise(read_pfm(ours))
    noise_theirs, mean_theirs = relative_noise(read_glslppm(theirs))
    print(f"kousen  {ours}: relative noise {noise_ours:.4f} (patch mean {mean_ours:.4g})")
    print(f"glslppm {theirs}: relative noise {noise_theirs:.4f} (patch mean {mean_theirs:.4g})")
    print(f"kousen / glslppm noise: {noise_ours / noise_theirs:.3f}")


if __name__ == "__main__":
    main()
