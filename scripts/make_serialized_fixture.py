#!/usr/bin/env python3
"""Writes the Mitsuba .serialized test fixture and checks it with Mitsuba 3's own loader.

    pip install mitsuba numpy
    python3 scripts/make_serialized_fixture.py crates/scene/tests/data/two-meshes.serialized

Two meshes in one file (format version 4, f32): a triangle with normals and texture
coordinates, and a square of two triangles without them; the table of their offsets at the
end. Mitsuba must read back the positions and faces written, or the script fails.
"""
import struct
import sys
import zlib

import mitsuba as mi
import numpy as np

MESHES = [
    ("triangle", [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]],
     [[0, 0, 1]] * 3, [[0, 0], [1, 0], [0, 1]]),
    ("square", [[0, 0, 2], [2, 0, 2], [2, 2, 2], [0, 2, 2]], [[0, 1, 2], [0, 2, 3]], None, None),
]


def mesh_bytes(name, positions, faces, normals, uvs):
    flags = 0x1000 | (0x0001 if normals else 0) | (0x0002 if uvs else 0)
    body = struct.pack("<I", flags) + name.encode() + b"\0"
    body += struct.pack("<QQ", len(positions), len(faces))
    for values in (positions, normals, uvs):
        if values:
            body += np.asarray(values, "<f4").tobytes()
    body += np.asarray(faces, "<u4").tobytes()
    return struct.pack("<HH", 0x041C, 4) + zlib.compress(body)


def main():
    out = sys.argv[1]
    blobs = [mesh_bytes(*m) for m in MESHES]
    offsets, at = [], 0
    for blob in blobs:
        offsets.append(at)
        at += len(blob)
    data = b"".join(blobs) + struct.pack(f"<{len(offsets)}Q", *offsets)
    data += struct.pack("<I", len(blobs))
    with open(out, "wb") as f:
        f.write(data)
    mi.set_variant("scalar_rgb")
    for i, (_, positions, faces, _, _) in enumerate(MESHES):
        shape = mi.load_dict({"type": "serialized", "filename": out, "shape_index": i})
        read = np.array(shape.vertex_positions_buffer()).reshape(-1, 3)
        assert np.array_equal(read, np.asarray(positions, float)), (i, read)
        assert np.array_equal(np.array(shape.faces_buffer()).reshape(-1, 3), faces)
    print(f"wrote {out} ({len(data)} bytes); Mitsuba reads both meshes back")


if __name__ == "__main__":
    main()
