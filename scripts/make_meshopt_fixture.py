#!/usr/bin/env python3
"""Writes crates/scene/tests/data/meshopt-sphere.gltf and meshopt-sphere-khr.gltf (each with
its fallback .bin): small glTF files whose buffer views are compressed by meshoptimizer's own
encoder, the first as EXT_meshopt_compression (attribute codec version 0), the second as
KHR_meshopt_compression (version 1: control and channel modes), with every plain view kept in
a fallback buffer that holds the data, so a test can load each both ways.

  pip install numpy meshoptimizer   (the PyPI package builds the C++ library)
  python3 scripts/make_meshopt_fixture.py crates/scene/tests/data

The index codec keeps each triangle's winding but may start it at another corner, so the
TRIANGLES view's plain bytes are the reference decoder's (the INDICES one's are the input).

What it holds: a sphere (positions float, texture coordinates as normalized u16, normals as octahedral
bytes under the OCTAHEDRAL filter), its indices twice (u16 as TRIANGLES, u32 as INDICES),
and three instances (EXT_mesh_gpu_instancing) whose translations use the EXPONENTIAL filter
and rotations the QUATERNION filter. The filters' encodings are written here after the
extension's Appendix B; the expected (plain) values are what meshoptimizer's reference
decoder and filters make of them.
"""
import base64
import json
import math
import os
import sys

import meshoptimizer as mo
import numpy as np


def sphere(rings=12, segments=20):
    positions, uvs, indices = [], [], []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            positions.append([math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi)])
            uvs.append([s / segments, r / rings])
    for r in range(rings):
        for s in range(segments):
            a = r * (segments + 1) + s
            b = a + segments + 1
            indices += [a, b, a + 1, a + 1, b, b + 1]
    return np.array(positions, np.float32), np.array(uvs, np.float32), np.array(indices, np.uint32)


def octahedral_bytes(normals):
    """Appendix B's octahedral input with K = 8: x, y, 1.0 as 127, and a zero pad."""
    out = np.zeros((len(normals), 4), np.int8)
    for i, n in enumerate(normals):
        n = n / np.abs(n).sum()
        x, y = n[0], n[1]
        if n[2] < 0:
            x, y = (1 - abs(n[1])) * math.copysign(1, n[0]), (1 - abs(n[0])) * math.copysign(1, n[1])
        out[i] = [round(x * 127), round(y * 127), 127, 0]
    return out


def quaternion_shorts(quaternions, bits=12):
    """Appendix B's quaternion input: the three smaller components scaled by sqrt(2) in K-bit
    integers, the largest's index in the last component's low bits."""
    one = (1 << (bits - 1)) - 1
    out = np.zeros((len(quaternions), 4), np.int16)
    for i, q in enumerate(quaternions):
        largest = int(np.argmax(np.abs(q)))
        if q[largest] < 0:
            q = -q
        rest = [q[(largest + k) % 4] for k in (1, 2, 3)]
        out[i] = [round(c * math.sqrt(2) * one) for c in rest] + [(one & ~3) | largest]
    return out


def exponential_words(values):
    """Appendix B's exponential input: an 8-bit exponent over a 24-bit mantissa."""
    out = np.zeros(values.shape, np.uint32)
    for index, v in np.ndenumerate(values):
        exponent = 0 if v == 0 else math.frexp(float(v))[1] - 23
        mantissa = round(float(v) / 2.0 ** exponent)
        out[index] = ((exponent & 0xFF) << 24) | (mantissa & 0xFFFFFF)
    return out


def write(folder, name, extension_name, vertex_version):
    mo.encode_vertex_version(vertex_version)
    mo.encode_index_version(1)
    positions, uvs, indices = sphere()
    optimized = np.zeros_like(indices)
    mo.optimize_vertex_cache(optimized, indices, len(indices), len(positions))
    indices = optimized
    normals = octahedral_bytes(positions)
    translations = exponential_words(np.array([[0, 0, 0], [2.5, 0.125, -1.75], [-3.0, 1e-3, 40.0]], np.float32))
    angle = 0.7
    rotations = quaternion_shorts(np.array([[0, 0, 0, 1], [0, math.sin(angle / 2), 0, math.cos(angle / 2)],
                                            [0.5, -0.5, 0.5, 0.5]], np.float64))

    # (plain bytes, compressed bytes, byteStride, count, mode, filter)
    views = []

    def add(plain, stride, mode, filter_name="NONE", encoded=None):
        count = len(plain) // stride
        if mode == "ATTRIBUTES":
            compressed = mo.encode_vertex_buffer(np.frombuffer(encoded or plain, np.uint8).reshape(count, stride), count, stride)
        elif mode == "TRIANGLES":
            index = np.frombuffer(plain, np.uint16 if stride == 2 else np.uint32).astype(np.uint32)
            compressed = mo.encode_index_buffer(index, count, int(index.max()) + 1)
            # The codec may turn a triangle's indices (a, b, c) into (b, c, a): the plain
            # bytes are what the reference decoder gives.
            # (The binding returns the decoder's raw output, `count` indices of `stride` bytes.)
            decoded = mo.decode_index_buffer(count, stride, compressed)
            plain = np.asarray(decoded).tobytes()[: count * stride]
        else:
            index = np.frombuffer(plain, np.uint16 if stride == 2 else np.uint32).astype(np.uint32)
            compressed = mo.encode_index_sequence(index, count, int(index.max()) + 1)
        views.append((plain, compressed, stride, count, mode, filter_name))
        return len(views) - 1

    def filtered(encoded, stride, decode_filter):
        raw = np.frombuffer(encoded, np.uint8).copy()
        return bytes(decode_filter(raw, len(raw) // stride, stride))

    position_view = add(positions.tobytes(), 12, "ATTRIBUTES")
    uv_view = add(np.round(uvs * 65535).astype(np.uint16).tobytes(), 4, "ATTRIBUTES")
    normal_view = add(filtered(normals.tobytes(), 4, mo.decode_filter_oct), 4, "ATTRIBUTES", "OCTAHEDRAL", normals.tobytes())
    triangles_view = add(indices.astype(np.uint16).tobytes(), 2, "TRIANGLES")
    sequence_view = add(indices.astype(np.uint32).tobytes(), 4, "INDICES")
    translation_view = add(filtered(translations.tobytes(), 12, mo.decode_filter_exp), 12, "ATTRIBUTES", "EXPONENTIAL", translations.tobytes())
    rotation_view = add(filtered(rotations.tobytes(), 8, mo.decode_filter_quat), 8, "ATTRIBUTES", "QUATERNION", rotations.tobytes())

    compressed_bin, plain_bin, buffer_views = bytearray(), bytearray(), []
    for plain, compressed, stride, count, mode, filter_name in views:
        while len(plain_bin) % 4:
            plain_bin.append(0)
        while len(compressed_bin) % 4:
            compressed_bin.append(0)
        extension = {"buffer": 0, "byteOffset": len(compressed_bin), "byteLength": len(compressed),
                     "byteStride": stride, "count": count, "mode": mode}
        if filter_name != "NONE":
            extension["filter"] = filter_name
        view = {"buffer": 1, "byteOffset": len(plain_bin), "byteLength": len(plain),
                "extensions": {extension_name: extension}}
        if mode == "ATTRIBUTES":
            view["byteStride"] = stride
        buffer_views.append(view)
        plain_bin += plain
        compressed_bin += compressed

    def accessor(view, component, count, kind, normalized=False, extra=None):
        a = {"bufferView": view, "componentType": component, "count": count, "type": kind}
        if normalized:
            a["normalized"] = True
        a.update(extra or {})
        return a

    vertex_count = len(positions)
    accessors = [
        accessor(position_view, 5126, vertex_count, "VEC3", extra={"min": [-1, -1, -1], "max": [1, 1, 1]}),
        accessor(uv_view, 5123, vertex_count, "VEC2", normalized=True),
        accessor(normal_view, 5120, vertex_count, "VEC3", normalized=True),
        accessor(triangles_view, 5123, len(indices), "SCALAR"),
        accessor(sequence_view, 5125, len(indices), "SCALAR"),
        accessor(translation_view, 5126, 3, "VEC3"),
        accessor(rotation_view, 5122, 3, "VEC4", normalized=True),
    ]
    attributes = {"POSITION": 0, "TEXCOORD_0": 1, "NORMAL": 2}
    document = {
        "asset": {"version": "2.0", "generator": "scripts/make_meshopt_fixture.py"},
        "extensionsUsed": [extension_name, "EXT_mesh_gpu_instancing", "KHR_mesh_quantization"],
        "extensionsRequired": [extension_name, "KHR_mesh_quantization"],
        "buffers": [
            {"uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(compressed_bin)).decode(),
             "byteLength": len(compressed_bin)},
            {"uri": f"{name}-fallback.bin", "byteLength": len(plain_bin),
             "extensions": {extension_name: {"fallback": True}}},
        ],
        "bufferViews": buffer_views,
        "accessors": accessors,
        "meshes": [{"primitives": [{"attributes": attributes, "indices": 3},
                                   {"attributes": attributes, "indices": 4}]}],
        "nodes": [{"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {
            "attributes": {"TRANSLATION": 5, "ROTATION": 6}}}}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, f"{name}.gltf"), "w") as f:
        json.dump(document, f, indent=1)
    with open(os.path.join(folder, f"{name}-fallback.bin"), "wb") as f:
        f.write(plain_bin)
    print(f"{name}: {len(compressed_bin)} compressed bytes, {len(plain_bin)} plain")


def main(folder):
    write(folder, "meshopt-sphere", "EXT_meshopt_compression", 0)
    write(folder, "meshopt-sphere-khr", "KHR_meshopt_compression", 1)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "crates/scene/tests/data")
