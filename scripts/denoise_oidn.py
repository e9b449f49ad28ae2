#!/usr/bin/env python3
"""Denoises a kousen render with Intel Open Image Denoise, guided by its albedo and normal.

    pip install numpy oidn tbb     # OIDN 1.4 through the `oidn` binding; tbb brings libtbb
    kousen render SCENE -o out.pfm --denoise-guides ...
    LD_LIBRARY_PATH=$(python3 -c 'import sys; print(sys.prefix)')/lib \\
        python3 scripts/denoise_oidn.py out.pfm -o clean.pfm [--no-guides]

Reads OUT.pfm and the guides `kousen render --denoise-guides` writes beside it
(OUT.albedo.pfm, OUT.normal.pfm) and writes the denoised image as PFM, linear, as OIDN's
"RT" filter makes it from HDR input. --no-guides denoises the colour alone, for comparison.
"""
import argparse
import ctypes
import sys
from pathlib import Path

import numpy as np


def read_pfm(path: Path) -> np.ndarray:
    """A colour PFM as float32 rows top to bottom (PFM stores them bottom up)."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"PF":
            sys.exit(f"{path}: not a colour PFM")
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        dtype = "<f4" if scale < 0 else ">f4"
        pixels = np.frombuffer(f.read(), dtype=dtype).reshape(height, width, 3)
    return np.ascontiguousarray(pixels[::-1], dtype=np.float32)


def write_pfm(path: Path, image: np.ndarray) -> None:
    height, width, _ = image.shape
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1\n" % (width, height))
        f.write(np.ascontiguousarray(image[::-1], dtype="<f4").tobytes())


def guide_path(image: Path, name: str) -> Path:
    return image.with_name(f"{image.stem}.{name}{image.suffix}")


def denoise(color: np.ndarray, albedo=None, normal=None) -> np.ndarray:
    import oidn

    library = getattr(oidn, "__lib_oidn")
    set_bool = library.oidnSetFilter1b
    set_bool.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_bool]
    height, width, _ = color.shape
    output = np.zeros_like(color)
    device = oidn.NewDevice()
    oidn.CommitDevice(device)
    rt = oidn.NewFilter(device, "RT")
    # The arrays must outlive the filter's execution: OIDN reads them in place.
    images = [("color", color), ("albedo", albedo), ("normal", normal), ("output", output)]
    for name, data in images:
        if data is not None:
            oidn.SetSharedFilterImage(rt, name, data, oidn.FORMAT_FLOAT3, width, height)
    set_bool(rt, b"hdr", True)
    oidn.CommitFilter(rt)
    oidn.ExecuteFilter(rt)
    error = oidn.GetDeviceError(device)
    oidn.ReleaseFilter(rt)
    oidn.ReleaseDevice(device)
    if error != 0:
        sys.exit(f"OIDN failed (error {error})")
    return output


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("image", type=Path, help="kousen's render, a .pfm")
    parser.add_argument("-o", "--output", type=Path, required=True)
    parser.add_argument("--no-guides", action="store_true", help="the colour alone")
    args = parser.parse_args()
    color = read_pfm(args.image)
    guides = {}
    if not args.no_guides:
        for name in ("albedo", "normal"):
            path = guide_path(args.image, name)
            if not path.exists():
                sys.exit(f"{path}: missing (render with --denoise-guides, or pass --no-guides)")
            guides[name] = read_pfm(path)
    write_pfm(args.output, denoise(color, **guides))


if __name__ == "__main__":
    main()
