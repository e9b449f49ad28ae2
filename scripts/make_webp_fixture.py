#!/usr/bin/env python3
"""Writes the lossy WebP test fixture and libwebp's own decoding of it.

    pip install pillow   # Pillow's WebP codec is libwebp
    python3 scripts/make_webp_fixture.py crates/scene/tests/data

`webp-lossy.webp` is a 24x16 picture (hue across, brightness down, alpha falling to the right)
encoded lossy (VP8, alpha in an ALPH chunk) by libwebp; `webp-lossy-libwebp.png` is what
libwebp decodes it to, the reference kousen's decoder (the `image` crate's, image-webp) is
compared with in crates/scene/tests/gltf_materials.rs.
"""
import colorsys
import sys
from pathlib import Path

from PIL import Image

WIDTH, HEIGHT = 24, 16


def picture() -> Image.Image:
    image = Image.new("RGBA", (WIDTH, HEIGHT))
    for y in range(HEIGHT):
        for x in range(WIDTH):
            r, g, b = colorsys.hsv_to_rgb(x / WIDTH, 0.8, 1.0 - 0.6 * y / (HEIGHT - 1))
            alpha = 255 - round(200 * x / (WIDTH - 1))
            image.putpixel((x, y), (round(255 * r), round(255 * g), round(255 * b), alpha))
    return image


def main() -> None:
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "crates/scene/tests/data")
    webp = out / "webp-lossy.webp"
    picture().save(webp, "WEBP", lossless=False, quality=80, method=6, exact=True)
    Image.open(webp).convert("RGBA").save(out / "webp-lossy-libwebp.png")
    print(f"wrote {webp} ({webp.stat().st_size} bytes) and its libwebp decoding")


if __name__ == "__main__":
    main()
