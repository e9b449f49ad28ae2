#!/usr/bin/env python3
"""Mitsuba 3's `roughplastic` diffuse lobe at a few angles, the reference numbers of
render::plastic's test `rough_coat_matches_mitsubas_roughplastic`.

Prints T(mu)/T(1) (the coat's tabulated transmittance, relative to head-on) and
scale * T(1)^2 (the base's scale times the head-on transmittance squared) for a GGX coat of
alpha 0.09, ior 1.5, from the diffuse component's eval (diffuse_reflectance 0.5) with the
outgoing direction straight up. Needs `pip install mitsuba` and, on machines without a system
LLVM that Dr.Jit finds, DRJIT_LIBLLVM_PATH (see ANCHORS.md)."""
import math

import mitsuba as mi

mi.set_variant("scalar_rgb")
ALPHA, IOR, RHO = 0.09, 1.5, 0.5
bsdf = mi.load_dict({
    "type": "roughplastic", "distribution": "ggx", "alpha": ALPHA,
    "int_ior": IOR, "ext_ior": 1.0,
    "diffuse_reflectance": {"type": "rgb", "value": [RHO] * 3},
})
context = mi.BSDFContext()
context.component = 1  # the diffuse lobe alone


def diffuse(mu_in, mu_out):
    """rho / pi * scale * T(mu_in) * T(mu_out)."""
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(math.sqrt(1 - mu_in ** 2), 0, mu_in)
    wo = mi.Vector3f(-math.sqrt(1 - mu_out ** 2), 0, mu_out)
    return bsdf.eval(context, si, wo)[0] / mu_out


head_on = diffuse(1.0, 1.0)
for mu in [0.8, 0.5, 0.3, 0.1, 0.03]:
    print(f"T({mu}) / T(1) = {diffuse(mu, 1.0) / head_on:.5f}")
print(f"scale * T(1)^2 = {head_on * math.pi / RHO:.5f}")
