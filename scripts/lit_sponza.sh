#!/bin/sh
# Crytek Sponza has no light and no camera. This makes a lit copy for benchmarks: the shared
# OBJ and MTL plus one emissive quad (3000 × 800 units, radiance 8, facing down) under the
# roof at y = 1100, textures linked. Usage: scripts/lit_sponza.sh SHARED_SCENES_DIR OUT_DIR
set -eu
src="$1/crytek-sponza"
out="$2"
mkdir -p "$out"
ln -sfn "$(cd "$src" && pwd)/textures" "$out/textures"
cp "$src/sponza.mtl" "$out/sponza.mtl"
printf '\nnewmtl kousen_light\nKd 0 0 0\nKe 8 8 8\n' >> "$out/sponza.mtl"
cp "$src/sponza.obj" "$out/sponza.obj"
printf '\ng light\nusemtl kousen_light\nv -1500 1100 -400\nv 1500 1100 -400\nv 1500 1100 400\nv -1500 1100 400\nf -4 -3 -2\nf -4 -2 -1\n' >> "$out/sponza.obj"
