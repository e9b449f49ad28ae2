#!/usr/bin/env python3
"""Render a glTF scene with Mitsuba 3 under kousen's material rules: an independent reference.

Written for and tested with Mitsuba 3.9.1 / Dr.Jit 1.5.0 (`pip install mitsuba numpy`), variant
`llvm_ad_rgb` (the default here) or `scalar_rgb` (needs nothing else, but is much slower).

The llvm variants need a newer LLVM than Debian's default; on this project's machines:

    apt-get install libllvm19
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
    python3 scripts/mitsuba_reference.py scenes/cornell-box.gltf out.exr \
        --width 64 --height 64 --spp 16384 --seed 1

Output: an OpenEXR file of float32 linear RGB radiance (no exposure, no tone mapping).

How the scene is read (the glTF is parsed here, with json and numpy; Mitsuba's own loaders are
not used, so nothing about the mapping is hidden):
- Geometry: every triangle primitive (mode 4) of every node reachable from the default scene,
  placed by the node's world transform (matrix or TRS, parents included). Normals go through the
  cofactor of the linear part; a mirroring transform swaps two vertices of each triangle so the
  front face (counter-clockwise winding) stays the front face. Vertex normals become Mitsuba's
  shading normals (missing ones are smoothed over the primitive, area-weighted).
- Materials (kousen's rules, DESIGN.md "Materials", crates/scene/src/gltf/materials.rs): glTF's
  mix(dielectric, metal, metallic) with the dielectric mix(opaque, glass, transmission), as a
  blend of up to three surfaces with those probabilities (equal ones merged), nested Mitsuba
  `blendbsdf`s where there is more than one:
  the glass -> dielectric, ior from KHR_materials_ior (1.5),
  exterior ior exactly 1, reflectance and transmittance tinted by baseColor (kousen tints every
  bounce off glass); roughness < 0.01 -> smooth: `dielectric` when KHR_materials_volume
  thicknessFactor > 0, else `thindielectric`; rougher -> `roughdielectric`, GGX of alpha =
  roughness^2, visible normals sampled (solid only: Mitsuba has no rough thin sheet). A solid's
  KHR_materials_volume attenuation (colour after distance) -> a `homogeneous` interior medium of
  albedo 0 and sigma_t = -ln(colour) / distance, rendered with `volpath` (kousen's Beer-Lambert
  absorption).
  the metal with roughness < 0.5 -> Mitsuba's `principled` with metallic 1 and base_color =
  baseColor: a GGX lobe (visible normals sampled; Mitsuba's Smith term is the separable one,
  as kousen's) of alpha = roughness^2 (at least 0.001: a smooth metal, roughness < 0.01, is a
  mirror to well under a pixel at these sizes) whose Fresnel is Schlick's from F0 = baseColor
  to white, glTF's conductor Fresnel as kousen has it (crates/render/src/conductor.rs;
  Mitsuba's `conductor` with material "none" would reflect baseColor at every angle);
  rougher -> Lambertian `diffuse`, reflectance = baseColor.
  the opaque dielectric with roughness < 0.5 (unless ior is 1 or KHR_materials_specular's
  specularFactor is 0) -> plastic, coat of int_ior = ior over diffuse_reflectance = baseColor,
  exterior ior exactly 1, `nonlinear` off: smooth (`plastic`) below roughness 0.01, else
  `roughplastic`, GGX of alpha = roughness^2 (visible normals). Mitsuba's `plastic` is kousen's
  model (render/src/plastic.rs), and so is its `roughplastic` since kousen's session 24.
  Otherwise -> Lambertian `diffuse`, reflectance = baseColor.
  Diffuse, plastic and the conductors are wrapped in `twosided`, since kousen's rays hit and scatter off both
  faces of every triangle (Mitsuba's opaque BSDFs are black from behind by default).
- Emission: emissiveFactor x KHR_materials_emissive_strength, as an `area` emitter. Mitsuba's
  area light emits to the side of the surface normal only, so emissive primitives are given no
  vertex normals: the normal is then the geometric one, fixed by the counter-clockwise winding,
  which is exactly kousen's front face. doubleSided emitters are refused (not needed yet).
- Punctual lights (KHR_lights_punctual) on nodes: `point` -> Mitsuba `point` (intensity =
  color x intensity, candela = power per steradian in kousen's units), `directional` ->
  `directional` (irradiance = color x intensity, lux), both placed by the node's world
  transform (lights shine down their local -z). Spot lights are refused: Mitsuba's spot
  falloff is not glTF's. `--point X,Y,Z --point-intensity R,G,B` adds a point light to any
  scene (kousen's tests add the same light in code).
- Sky: `--sky-map FILE --sky-rotate DEG` -> Mitsuba `envmap` turned to kousen's orientation
  (see sky_emitter).
- Nesting: `--exterior NAME=SOLID` says material NAME lies inside the solid dielectric SOLID
  (kousen finds this from the geometry, crates/render/src/nesting.rs): NAME's dielectric and
  plastic members get ext_ior = SOLID's ior, and its shapes SOLID's absorbing medium as their
  exterior medium.
- Camera: the first camera node in the scene's depth-first node order (`--camera I`: the I-th,
  as kousen's `--camera` counts them; `--camera-medium NAME` puts it inside the absorbing
  medium of material NAME, as kousen's own camera would find itself); perspective yfov
  (vertical field of view); the aspect ratio comes from the image size. glTF cameras look down
  their local -z with +y up. `--aperture-radius R --focus-distance D`: Mitsuba's `thinlens`
  sensor, the same thin lens as kousen's. Pixels: `box` reconstruction filter (each sample lands in the one
  pixel whose area it was drawn from), i.e. the average of radiance over the pixel's area.
- Integrator: `path` with max_depth -1 (unlimited, Russian roulette from depth 5 unless
  --max-depth/--rr-depth say otherwise): unbiased, converges to the same image as any other
  correct renderer.
- Large sample counts are split into passes of at most --pass-samples samples in total (the
  llvm variants keep a whole pass's wavefront in memory); pass i of seed s uses Mitsuba seed
  s * 1_000_003 + i, and the passes are averaged (equal spp each, so the mean is exact).
"""
import argparse
import base64
import json
import math
import os
import struct
import sys
import time

import numpy as np

MIRROR_MAX_ROUGHNESS = 0.01
DIFFUSE_MIN_ROUGHNESS = 0.5
DEFAULT_IOR = 1.5

COMPONENT_DTYPES = {5120: "i1", 5121: "u1", 5122: "<i2", 5123: "<u2", 5125: "<u4", 5126: "<f4"}
TYPE_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


# ----------------------------------------------------------------------------------- glTF reading

def load_gltf(path):
    """The JSON document and its buffers (bytes), from .gltf (+ files or data URIs) or .glb."""
    raw = open(path, "rb").read()
    glb_bin = None
    if raw[:4] == b"glTF":
        _, _, length = struct.unpack_from("<4sII", raw, 0)
        pos, doc = 12, None
        while pos < length:
            clen, ctype = struct.unpack_from("<II", raw, pos)
            chunk = raw[pos + 8:pos + 8 + clen]
            if ctype == 0x4E4F534A:
                doc = json.loads(chunk.decode("utf-8"))
            elif ctype == 0x004E4942:
                glb_bin = chunk
            pos += 8 + clen
    else:
        doc = json.loads(raw.decode("utf-8"))
    base = os.path.dirname(os.path.abspath(path))
    buffers = []
    for i, b in enumerate(doc.get("buffers", [])):
        uri = b.get("uri")
        if uri is None:
            if glb_bin is None:
                raise ValueError("buffer %d has no uri and there is no GLB binary chunk" % i)
            buffers.append(glb_bin)
        elif uri.startswith("data:"):
            buffers.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            from urllib.parse import unquote
            buffers.append(open(os.path.join(base, unquote(uri)), "rb").read())
    return doc, buffers


def read_accessor(doc, buffers, index):
    """An accessor as a float64 or integer numpy array of shape (count, components)."""
    a = doc["accessors"][index]
    if "sparse" in a:
        raise NotImplementedError("sparse accessors are not supported (accessor %d)" % index)
    ncomp = TYPE_COMPONENTS[a["type"]]
    dtype = np.dtype(COMPONENT_DTYPES[a["componentType"]])
    count = a["count"]
    if "bufferView" not in a:
        return np.zeros((count, ncomp), dtype=dtype)
    bv = doc["bufferViews"][a["bufferView"]]
    blob = buffers[bv["buffer"]]
    offset = bv.get("byteOffset", 0) + a.get("byteOffset", 0)
    elem = dtype.itemsize * ncomp
    stride = bv.get("byteStride", elem)
    if stride == elem:
        arr = np.frombuffer(blob, dtype=dtype, count=count * ncomp, offset=offset)
        arr = arr.reshape(count, ncomp)
    else:
        rows = [np.frombuffer(blob, dtype=dtype, count=ncomp, offset=offset + k * stride)
                for k in range(count)]
        arr = np.array(rows, dtype=dtype).reshape(count, ncomp)
    if a.get("normalized", False):
        info = np.iinfo(dtype)
        arr = np.maximum(arr.astype(np.float64) / info.max, -1.0)
    return arr


def quat_to_matrix(q):
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def local_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # column-major
    m = np.eye(4)
    t = node.get("translation", [0.0, 0.0, 0.0])
    r = node.get("rotation", [0.0, 0.0, 0.0, 1.0])
    s = node.get("scale", [1.0, 1.0, 1.0])
    m[:3, :3] = quat_to_matrix(r) @ np.diag(s)
    m[:3, 3] = t
    return m


def walk_nodes(doc):
    """(node index, world matrix) for every node of the default scene, depth first."""
    scene_index = doc.get("scene", 0)
    if "scenes" in doc and doc["scenes"]:
        roots = doc["scenes"][scene_index].get("nodes", [])
    else:
        roots = list(range(len(doc.get("nodes", []))))
    out = []

    def visit(i, parent):
        node = doc["nodes"][i]
        world = parent @ local_matrix(node)
        out.append((i, world))
        for c in node.get("children", []):
            visit(c, world)

    for r in roots:
        visit(r, np.eye(4))
    return out


def smooth_normals(p, tri):
    n = np.zeros_like(p)
    fn = np.cross(p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]])  # 2 x area weighted
    for k in range(3):
        np.add.at(n, tri[:, k], fn)
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return np.where(length > 0, n / np.maximum(length, 1e-30), np.array([0.0, 0.0, 1.0]))


# ------------------------------------------------------------------------------------- materials

def material_info(doc, index):
    """kousen's reading of a glTF material: ([(probability, kind, params)], emission rgb,
    double_sided, name)."""
    m = doc["materials"][index] if index is not None else {}
    pbr = m.get("pbrMetallicRoughness", {})
    for tex in ("baseColorTexture", "metallicRoughnessTexture"):
        if tex in pbr:
            raise NotImplementedError("material %r: textures are not supported" % m.get("name"))
    if "emissiveTexture" in m:
        raise NotImplementedError("material %r: textures are not supported" % m.get("name"))
    if "KHR_materials_dispersion" in m.get("extensions", {}):
        raise NotImplementedError("material %r: KHR_materials_dispersion (Mitsuba's RGB variants "
                                  "have no dispersion)" % m.get("name"))
    if m.get("alphaMode", "OPAQUE") != "OPAQUE":
        raise NotImplementedError("material %r: alphaMode is not supported" % m.get("name"))
    base = [float(c) for c in pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])[:3]]
    metallic = float(pbr.get("metallicFactor", 1.0))
    roughness = float(pbr.get("roughnessFactor", 1.0))
    ext = m.get("extensions", {})
    transmission = float(ext.get("KHR_materials_transmission", {}).get("transmissionFactor", 0.0))
    ior = float(ext.get("KHR_materials_ior", {}).get("ior", DEFAULT_IOR))
    thickness = float(ext.get("KHR_materials_volume", {}).get("thicknessFactor", 0.0))
    # glTF's mix(dielectric, metal, metallic), the dielectric mix(opaque, glass, transmission):
    # kousen's blend of up to three surfaces (crates/scene/src/gltf/materials.rs), each with its
    # probability; equal surfaces merge.
    if roughness < MIRROR_MAX_ROUGHNESS:
        metal = ("mirror", {"color": base})
    elif roughness < DIFFUSE_MIN_ROUGHNESS:
        metal = ("rough", {"color": base, "alpha": roughness * roughness})
    else:
        metal = ("diffuse", {"color": base})
    if ior == 0.0:
        glass = ("mirror", {"color": base})
    else:
        params = {"color": base, "ior": ior, "thin": thickness == 0.0}
        volume = ext.get("KHR_materials_volume", {})
        distance = float(volume.get("attenuationDistance", math.inf))
        color = [float(c) for c in volume.get("attenuationColor", [1.0, 1.0, 1.0])]
        if not params["thin"] and math.isfinite(distance):
            # kousen's absorption_from_attenuation: -ln(colour) / distance, colour >= e^-20.
            params["absorption"] = [-math.log(max(c, math.exp(-20.0))) / distance
                                    for c in color]
        glass = ("dielectric", params)
        if roughness >= MIRROR_MAX_ROUGHNESS:
            glass = ("roughdielectric", dict(params, alpha=roughness * roughness))
    if (roughness < DIFFUSE_MIN_ROUGHNESS and ior != 1.0
            and float(ext.get("KHR_materials_specular", {}).get("specularFactor", 1.0)) > 0.0):
        if ior == 0.0:
            opaque = ("mirror", {"color": base})
        else:
            alpha = 0.0 if roughness < MIRROR_MAX_ROUGHNESS else roughness * roughness
            opaque = ("plastic", {"color": base, "ior": ior, "alpha": alpha})
    else:
        opaque = ("diffuse", {"color": base})
    members = []
    for probability, (kind, params) in ((metallic, metal),
                                        ((1.0 - metallic) * transmission, glass),
                                        ((1.0 - metallic) * (1.0 - transmission), opaque)):
        if probability <= 0.0:
            continue
        if kind == "roughdielectric" and params["thin"]:
            raise NotImplementedError("material %r: Mitsuba has no rough thin sheet"
                                      % m.get("name"))
        same = [k for k, member in enumerate(members) if member[1:] == (kind, params)]
        if same:
            members[same[0]] = (members[same[0]][0] + probability, kind, params)
        else:
            members.append((probability, kind, params))
    strength = float(ext.get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0))
    emission = [float(c) * strength for c in m.get("emissiveFactor", [0.0, 0.0, 0.0])]
    return members, emission, bool(m.get("doubleSided", False)), m.get("name", str(index))


def mitsuba_blend(members):
    """A blend's members as nested `blendbsdf`s: the first with its probability, else the rest
    (Mitsuba's weight is the second BSDF's share)."""
    (probability, kind, params), rest = members[0], members[1:]
    if not rest:
        return mitsuba_bsdf(kind, params)
    left = sum(p for p, _, _ in rest)
    return {"type": "blendbsdf", "weight": left / (probability + left),
            "first": mitsuba_bsdf(kind, params), "second": mitsuba_blend(rest)}


def mitsuba_bsdf(kind, params):
    rgb = lambda c: {"type": "rgb", "value": c}
    if kind == "diffuse":
        return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": rgb(params["color"])}}
    if kind in ("mirror", "rough"):
        # Mitsuba's principled takes roughness and squares it into alpha (floored at 0.001).
        roughness = math.sqrt(params["alpha"]) if kind == "rough" else 0.0
        return {"type": "twosided", "bsdf": {"type": "principled", "metallic": 1.0,
                                             "roughness": roughness,
                                             "base_color": rgb(params["color"])}}
    if kind == "dielectric":
        return {"type": "thindielectric" if params["thin"] else "dielectric",
                "int_ior": params["ior"], "ext_ior": params.get("ext_ior", 1.0),
                "specular_reflectance": rgb(params["color"]),
                "specular_transmittance": rgb(params["color"])}
    if kind == "roughdielectric":
        return {"type": "roughdielectric", "distribution": "ggx", "alpha": params["alpha"],
                "sample_visible": True, "int_ior": params["ior"], "ext_ior": params.get("ext_ior", 1.0),
                "specular_reflectance": rgb(params["color"]),
                "specular_transmittance": rgb(params["color"])}
    if kind == "plastic" and params["alpha"] == 0.0:
        return {"type": "twosided", "bsdf": {"type": "plastic", "int_ior": params["ior"],
                                             "ext_ior": params.get("ext_ior", 1.0), "nonlinear": False,
                                             "diffuse_reflectance": rgb(params["color"])}}
    if kind == "plastic":
        return {"type": "twosided", "bsdf": {"type": "roughplastic", "distribution": "ggx",
                                             "alpha": params["alpha"], "sample_visible": True,
                                             "int_ior": params["ior"], "ext_ior": params.get("ext_ior", 1.0),
                                             "nonlinear": False,
                                             "diffuse_reflectance": rgb(params["color"])}}
    raise ValueError(kind)


# ----------------------------------------------------------------------------------------- scene

def gather_primitives(doc, buffers):
    """World-space (positions, normals or None, triangles, material index) per primitive."""
    prims = []
    for node_index, world in walk_nodes(doc):
        node = doc["nodes"][node_index]
        if "mesh" not in node:
            continue
        linear = world[:3, :3]
        mirrored = np.linalg.det(linear) < 0.0
        cof = np.stack([np.cross(linear[:, 1], linear[:, 2]),
                        np.cross(linear[:, 2], linear[:, 0]),
                        np.cross(linear[:, 0], linear[:, 1])], axis=1)  # det * inverse transpose
        if mirrored:
            cof = -cof
        for prim in doc["meshes"][node["mesh"]]["primitives"]:
            if prim.get("mode", 4) != 4:
                raise NotImplementedError("only triangle lists (mode 4) are supported")
            attrs = prim["attributes"]
            p = read_accessor(doc, buffers, attrs["POSITION"]).astype(np.float64)
            if "indices" in prim:
                tri = read_accessor(doc, buffers, prim["indices"]).astype(np.int64).reshape(-1, 3)
            else:
                tri = np.arange(len(p), dtype=np.int64).reshape(-1, 3)
            p = p @ linear.T + world[:3, 3]
            if mirrored:
                tri = tri[:, [0, 2, 1]]
            if "NORMAL" in attrs:
                n = read_accessor(doc, buffers, attrs["NORMAL"]).astype(np.float64) @ cof.T
                n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
            else:
                n = smooth_normals(p, tri)
            prims.append((p, n, tri, prim.get("material")))
    return prims


def nth_camera(doc, n):
    """The `n`-th camera node in depth-first node order (kousen's `--camera` index)."""
    found = 0
    for node_index, world in walk_nodes(doc):
        node = doc["nodes"][node_index]
        if "camera" in node:
            if found == n:
                cam = doc["cameras"][node["camera"]]
                if cam.get("type") != "perspective":
                    raise NotImplementedError("only perspective cameras are supported")
                return world, cam["perspective"]["yfov"]
            found += 1
    raise ValueError("the scene has no camera %d (%d cameras)" % (n, found))


def punctual_lights(doc, extra_points):
    """Mitsuba emitter dicts for the scene's KHR_lights_punctual lights and `extra_points`
    ((position, intensity) pairs)."""
    lights = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    out = []
    for node_index, world in walk_nodes(doc):
        ext = doc["nodes"][node_index].get("extensions", {}).get("KHR_lights_punctual")
        if ext is None:
            continue
        light = lights[ext["light"]]
        value = [c * light.get("intensity", 1.0) for c in light.get("color", [1.0, 1.0, 1.0])]
        kind = light["type"]
        if kind == "point":
            out.append({"type": "point", "position": world[:3, 3].tolist(),
                        "intensity": {"type": "rgb", "value": value}})
        elif kind == "directional":
            direction = -world[:3, 2] / np.linalg.norm(world[:3, 2])
            out.append({"type": "directional", "direction": direction.tolist(),
                        "irradiance": {"type": "rgb", "value": value}})
        else:
            raise NotImplementedError("light %d: %s lights (Mitsuba's spot falloff is not glTF's)"
                                      % (ext["light"], kind))
    for position, intensity in extra_points:
        out.append({"type": "point", "position": list(position),
                    "intensity": {"type": "rgb", "value": list(intensity)}})
    return out


def solid_of(doc, name):
    """The solid dielectric member's params of the material called `name` (its ior, and its
    absorption where it has one)."""
    for index in range(len(doc.get("materials", []))):
        members, _, _, found = material_info(doc, index)
        if found != name:
            continue
        for _, kind, params in members:
            if kind in ("dielectric", "roughdielectric") and not params["thin"]:
                return params
        raise ValueError("material %r is not a solid dielectric" % name)
    raise ValueError("no material called %r" % name)


def bilinear_upsample(bitmap, factor):
    """`bitmap` (H x W x 3) resampled `factor` times finer in each axis by kousen's bilinear rule
    (scene::SkyMap::radiance_at): texel (x, y)'s centre at ((x + 1/2)/W, (y + 1/2)/H), columns
    wrapping, rows clamped."""
    height, width = bitmap.shape[:2]
    s = (np.arange(width * factor) + 0.5) / factor - 0.5
    t = (np.arange(height * factor) + 0.5) / factor - 0.5
    left, top = np.floor(s), np.floor(t)
    a, b = (s - left)[None, :, None], (t - top)[:, None, None]
    x0 = left.astype(int) % width
    x1 = (x0 + 1) % width
    y0 = np.clip(top.astype(int), 0, height - 1)
    y1 = np.clip(top.astype(int) + 1, 0, height - 1)
    upper = bitmap[y0][:, x0] * (1 - a) + bitmap[y0][:, x1] * a
    lower = bitmap[y1][:, x0] * (1 - a) + bitmap[y1][:, x1] * a
    return upper * (1 - b) + lower * b


def sky_emitter(mi, path, rotate_degrees, log):
    """Mitsuba's `envmap` for kousen's `--sky-map PATH --sky-rotate DEG`. kousen's column u looks
    along azimuth 2*pi*(u - 1/2) from -Z towards +X (crates/scene/src/sky_map.rs), Mitsuba's along
    2*pi*u: the same map turned half a turn more about +Y. Both interpolate bilinearly, but
    where each puts a texel's sample and how each treats the poles and the seam is its own, so
    the map is handed over already interpolated by kousen's rule, 8x finer: Mitsuba's own
    interpolation then moves it by 1/16 of a texel at most."""
    bitmap = np.array(mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB,
                                              mi.Struct.Type.Float32, srgb_gamma=False))
    magnified = bilinear_upsample(bitmap, 8)
    log("sky map %s: %dx%d, resampled to %dx%d, turned %g deg"
        % (path, bitmap.shape[1], bitmap.shape[0], magnified.shape[1], magnified.shape[0],
           rotate_degrees))
    return {"type": "envmap",
            "bitmap": mi.Bitmap(magnified.astype(np.float32), pixel_format=mi.Bitmap.PixelFormat.RGB),
            "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], rotate_degrees + 180.0)}


def build_scene(mi, doc, buffers, width, height, max_depth, rr_depth, log, extra_points=(),
                camera=0, camera_medium=None, exteriors=None, sky=None, lens=None):
    exteriors = exteriors or {}
    world, yfov = nth_camera(doc, camera)
    eye = world[:3, 3]
    forward = -world[:3, 2] / np.linalg.norm(world[:3, 2])
    up = world[:3, 1] / np.linalg.norm(world[:3, 1])
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": max_depth, "rr_depth": rr_depth},
        "sensor": {
            "type": "perspective",
            "fov_axis": "y",
            "fov": math.degrees(yfov),
            "near_clip": 1e-3 * float(np.linalg.norm(eye) + 1.0),
            # Mitsuba's camera looks down its +z with +x to the image's LEFT; look_at builds
            # exactly that frame from the glTF camera's eye, forward and up.
            "to_world": mi.ScalarTransform4f().look_at(
                origin=eye.tolist(), target=(eye + forward).tolist(), up=up.tolist()),
            "film": {"type": "hdrfilm", "width": width, "height": height,
                     "pixel_format": "rgb", "component_format": "float32",
                     "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": 1},
        },
    }
    if lens:
        # kousen's --aperture-radius and --focus-distance: the same thin lens (Mitsuba's focus
        # distance, like kousen's, is along the view to the plane in focus).
        scene["sensor"]["type"] = "thinlens"
        scene["sensor"]["aperture_radius"] = lens[0]
        scene["sensor"]["focus_distance"] = lens[1]
    ntri = 0
    media = {}

    def medium_of(name, params):
        # Absorption only: a medium that scatters nothing (albedo 0).
        if name not in media:
            media[name] = mi.load_dict({
                "type": "homogeneous", "albedo": 0.0,
                "sigma_t": {"type": "rgb", "value": params["absorption"]}})
        return media[name]

    for k, (p, n, tri, mat) in enumerate(gather_primitives(doc, buffers)):
        members, emission, double_sided, name = material_info(doc, mat)
        params = next((q for _, _, q in members if "absorption" in q), {})
        around = None
        if name in exteriors:
            # Nested (kousen's render/src/nesting.rs): indices relative to the solid around,
            # whose medium surrounds this shape.
            around = solid_of(doc, exteriors[name])
            members = [(w, kind, dict(q, ext_ior=around["ior"])) for w, kind, q in members]
        emissive = max(emission) > 0.0
        # Winding against the given normals, for the record (Mitsuba shades with the normals).
        fn = np.cross(p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]])
        agree = np.einsum("ij,ij->i", fn, n[tri].sum(axis=1)) > 0.0
        if not agree.all():
            log("primitive %d (%s): %d of %d triangles wind against their normals"
                % (k, name, int((~agree).sum()), len(tri)))
        props = mi.Properties()
        props["bsdf"] = mi.load_dict(mitsuba_blend(members))
        if "absorption" in params:
            props["interior"] = medium_of(name, params)
        if around is not None and "absorption" in around:
            props["exterior"] = medium_of(exteriors[name], around)
        if emissive:
            if double_sided:
                raise NotImplementedError("material %r: double-sided emission" % name)
            props["emitter"] = mi.load_dict({"type": "area",
                                             "radiance": {"type": "rgb", "value": emission}})
        # Emitters get geometric normals only: Mitsuba's area light emits on the normal's side.
        with_normals = not emissive
        mesh = mi.Mesh("prim_%d" % k, vertex_count=len(p), face_count=len(tri),
                       has_vertex_normals=with_normals, props=props)
        params_m = mi.traverse(mesh)
        params_m["vertex_positions"] = mi.Float(p.astype(np.float32).ravel())
        if with_normals:
            params_m["vertex_normals"] = mi.Float(n.astype(np.float32).ravel())
        params_m["faces"] = mi.UInt32(tri.astype(np.uint32).ravel())
        params_m.update()
        scene["prim_%d" % k] = mesh
        ntri += len(tri)
        log("primitive %d: %s, %d triangles, %s%s" % (
            k, name, len(tri), " + ".join(
                ("%g " % p if len(members) > 1 else "") + kind
                + ("" if "dielectric" not in kind else
                   " ior %g %s" % (q["ior"], "thin" if q["thin"] else "solid"))
                for p, kind, q in members),
            (", emits %s (front face)" % [round(e, 6) for e in emission]) if emissive else "")
            + (", absorbs %s per unit" % [round(a, 6) for a in params["absorption"]]
               if "absorption" in params else "")
            + (", inside %r (ior %g)" % (exteriors[name], around["ior"]) if around else ""))
    for k, light in enumerate(punctual_lights(doc, extra_points)):
        scene["light_%d" % k] = light
        log("light %d: %s" % (k, light))
    log("%d triangles; camera eye %s forward %s up %s, yfov %.4f deg"
        % (ntri, eye.round(4).tolist(), forward.round(6).tolist(), up.round(6).tolist(),
           math.degrees(yfov)))
    if sky is not None:
        scene["sky"] = sky_emitter(mi, sky[0], sky[1], log)
    if camera_medium is not None:
        # The camera sits inside this material's medium (kousen finds that itself).
        if camera_medium not in media:
            raise ValueError("--camera-medium %r: no absorbing material of that name (%s)"
                             % (camera_medium, ", ".join(media) or "none"))
        scene["sensor"]["medium"] = media[camera_medium]
        log("camera inside the medium of %r" % camera_medium)
    if media:
        # The path tracer ignores media; its volumetric twin absorbs inside them.
        scene["integrator"]["type"] = "volpath"
        log("absorbing glass: volpath integrator")
    return mi.load_dict(scene)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("output", help="OpenEXR output (float32 linear RGB)")
    ap.add_argument("--width", type=int, default=64)
    ap.add_argument("--height", type=int, default=None, help="default: width")
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--variant", default="llvm_ad_rgb", help="llvm_ad_rgb (default) or scalar_rgb")
    ap.add_argument("--max-depth", type=int, default=-1)
    ap.add_argument("--rr-depth", type=int, default=5)
    ap.add_argument("--point", default=None, help="add a point light at X,Y,Z")
    ap.add_argument("--point-intensity", default="1,1,1",
                    help="its intensity R,G,B (power per steradian)")
    ap.add_argument("--camera", type=int, default=0, help="the I-th camera (default 0)")
    ap.add_argument("--camera-medium", default=None,
                    help="the camera sits inside this absorbing material's medium")
    ap.add_argument("--exterior", action="append", default=[], metavar="NAME=SOLID",
                    help="material NAME lies inside solid material SOLID (its indices relative "
                         "to SOLID's, SOLID's medium around it), as kousen finds itself")
    ap.add_argument("--sky-map", default=None,
                    help="light the scene with this equirectangular sky map, as kousen's --sky-map")
    ap.add_argument("--sky-rotate", type=float, default=0.0,
                    help="turn the sky map this many degrees about +Y, as kousen's --sky-rotate")
    ap.add_argument("--aperture-radius", type=float, default=0.0,
                    help="a thin lens of this radius (kousen's --aperture-radius; with --focus-distance)")
    ap.add_argument("--focus-distance", type=float, default=None,
                    help="its plane in focus, this far ahead of the eye along the view")
    ap.add_argument("--pass-samples", type=int, default=1 << 22,
                    help="most samples (pixels x spp) in one Mitsuba render call")
    args = ap.parse_args()
    if args.aperture_radius > 0 and args.focus_distance is None:
        ap.error("--aperture-radius needs --focus-distance (kousen --stats reports its autofocus)")
    height = args.height or args.width
    log = lambda s: print(s, file=sys.stderr, flush=True)

    import mitsuba as mi
    import drjit as dr
    mi.set_variant(args.variant)
    log("mitsuba %s, drjit %s, variant %s" % (mi.__version__, dr.__version__, args.variant))

    doc, buffers = load_gltf(args.scene)
    triple = lambda text: [float(x) for x in text.split(",")]
    extra_points = [(triple(args.point), triple(args.point_intensity))] if args.point else []
    scene = build_scene(mi, doc, buffers, args.width, height, args.max_depth, args.rr_depth, log,
                        extra_points, args.camera, args.camera_medium,
                        dict(e.split("=", 1) for e in args.exterior),
                        (args.sky_map, args.sky_rotate) if args.sky_map else None,
                        (args.aperture_radius, args.focus_distance) if args.aperture_radius > 0 else None)

    pixels = args.width * height
    per_pass = max(1, min(args.spp, args.pass_samples // pixels))
    passes = [per_pass] * (args.spp // per_pass)
    if args.spp % per_pass:
        passes.append(args.spp % per_pass)
    started = time.time()
    acc = np.zeros((height, args.width, 3), dtype=np.float64)
    for i, spp in enumerate(passes):
        seed = args.seed * 1_000_003 + i
        img = mi.render(scene, spp=spp, seed=seed)
        acc += np.array(img, dtype=np.float64)[..., :3] * spp
        if i == 0 or (i + 1) % 8 == 0 or i + 1 == len(passes):
            log("pass %d/%d (%d spp), %.1f s" % (i + 1, len(passes), spp, time.time() - started))
    img = (acc / args.spp).astype(np.float32)
    seconds = time.time() - started
    if not np.isfinite(img).all():
        raise RuntimeError("non-finite pixels")
    os.makedirs(os.path.dirname(os.path.abspath(args.output)) or ".", exist_ok=True)
    mi.Bitmap(img, pixel_format=mi.Bitmap.PixelFormat.RGB).write(args.output)
    log("%dx%d, %d spp in %d passes, %.1f s; channel means %s -> %s"
        % (args.width, height, args.spp, len(passes), seconds,
           img.reshape(-1, 3).mean(axis=0).round(6).tolist(), args.output))


if __name__ == "__main__":
    main()
