#!/usr/bin/env bash
# Shared set-up for run.sh and test.sh (CONTRACT §1): installs what is missing from Debian, extracts
# the scanned meshes of libcgal-demo into the data cache, and builds Release into build/.
# Idempotent: a second run installs nothing, extracts nothing and rebuilds only what changed.
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

# Debian packages aoeval needs. Everything comes from apt; nothing is downloaded from elsewhere.
# python3-numpy and python3-openimageio: the shipped Python plug-ins (plugins/examples).
# zlib1g-dev: the report viewer's compact data is deflated (reports/viewer.h).
# openarena-081-maps: OpenArena's Quake 3 levels, for the corpus's `oa-dm4` (issue 44);
# libirrlicht-doc: Irrlicht's demo level 20kdm2 (media/map-20kdm2.pk3.gz), the corpus's `q3-20kdm2`;
# assimp-testmodels also holds its CAD models.
packages=(
  build-essential cmake ninja-build pkg-config clang-format fonts-dejavu-core
  libembree-dev libtbb-dev libglm-dev
  libopenimageio-dev openimageio-tools libopenexr-dev
  libassimp-dev assimp-testmodels libcgal-demo
  openarena-081-maps libirrlicht-doc
  nlohmann-json3-dev libcli11-dev libsqlite3-dev sqlite3
  libgtest-dev libgmock-dev libbenchmark-dev libnlopt-cxx-dev libboost-dev
  libvulkan-dev mesa-vulkan-drivers vulkan-tools vulkan-validationlayers glslang-tools glslang-dev
  spirv-tools python3-matplotlib ccache python3-numpy python3-openimageio zlib1g-dev
)
# test.sh also drives Debian's chromium headless for the browser test of the reports (node comes
# from the machine, or Debian's nodejs + npm where it has none).
# The sanitizer stage (tools/sanitize.sh) builds with clang, its sanitizers and libFuzzer.
if [ "${1:-}" = "--test" ]; then
  # slurmctld, slurmd, slurm-client and munge: the one-node Slurm cluster of the --slurm test (issue 19).
  # blender: Cycles, the independent ray tracer that cycles_ao_test checks `aoeval reference`
  # against, and the maker of the glTF test asset (scenes/testdata/gltf/make_blender_asset.py).
  packages+=(chromium clang libclang-rt-14-dev slurmctld slurmd slurm-client munge blender)
  command -v node >/dev/null && command -v npm >/dev/null || packages+=(nodejs npm)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]})); then
  echo "bootstrap: installing ${missing[*]}" >&2
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends \
    "${missing[@]}" >&2
fi

# Scanned meshes (CONTRACT §6): extracted once from libcgal-demo's data tarball into the data folder
# that scene files address as "cache:meshes/..." (scenes/scene.h mesh_data_dirs: $AOEVAL_DATA, else
# $AOEVAL_CACHE, else the user's cache), so a fresh shared AOEVAL_CACHE still finds them.
cache_dir="${AOEVAL_DATA:-${AOEVAL_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/aoeval}}"
meshes=(bunny00.off ChineseDragon-10kv.off armadillo.off elephant.off)
need_extract=0
for m in "${meshes[@]}"; do [ -s "$cache_dir/meshes/$m" ] || need_extract=1; done
if ((need_extract)); then
  tarball=/usr/share/doc/libcgal-demo/data.tar.gz
  [ -f "$tarball" ] || { echo "bootstrap: $tarball is missing (package libcgal-demo)" >&2; exit 1; }
  mkdir -p "$cache_dir/meshes"
  tmp="$(mktemp -d)"
  tar -xzf "$tarball" -C "$tmp" "${meshes[@]/#/data/meshes/}"
  for m in "${meshes[@]}"; do mv "$tmp/data/meshes/$m" "$cache_dir/meshes/$m.tmp" && mv "$cache_dir/meshes/$m.tmp" "$cache_dir/meshes/$m"; done
  rm -rf "$tmp"
  echo "bootstrap: extracted ${#meshes[@]} meshes into $cache_dir/meshes" >&2
fi

# OpenArena's level oa_dm4 (issue 44, corpus `oa-dm4`): extracted once from the maps archive into
# "cache:levels/oa_dm4.bsp" (scenes/q3_bsp.h reads the .bsp; Debian's assimp cannot).
if [ ! -s "$cache_dir/levels/oa_dm4.bsp" ]; then
  pk3=/usr/share/games/openarena/baseoa/pak1-maps.pk3
  [ -f "$pk3" ] || { echo "bootstrap: $pk3 is missing (package openarena-081-maps)" >&2; exit 1; }
  mkdir -p "$cache_dir/levels"
  python3 -c 'import sys, zipfile; open(sys.argv[2], "wb").write(zipfile.ZipFile(sys.argv[1]).read("maps/oa_dm4.bsp"))' \
    "$pk3" "$cache_dir/levels/oa_dm4.bsp.tmp"
  mv "$cache_dir/levels/oa_dm4.bsp.tmp" "$cache_dir/levels/oa_dm4.bsp"
  echo "bootstrap: extracted oa_dm4.bsp into $cache_dir/levels" >&2
fi

# Irrlicht's Quake 3 demo level 20kdm2 (corpus `q3-20kdm2`): extracted once from the gzipped .pk3 that
# libirrlicht-doc installs into "cache:levels/20kdm2.bsp". Its map-20kdm2.txt beside it gives the
# author's terms (free to use, not to ship in a commercial product without permission): read in
# place, never copied into the repository.
if [ ! -s "$cache_dir/levels/20kdm2.bsp" ]; then
  pk3gz=/usr/share/doc/libirrlicht-dev/media/map-20kdm2.pk3.gz
  mkdir -p "$cache_dir/levels"
  if [ ! -f "$pk3gz" ]; then
    # A dpkg path-exclude of /usr/share/doc (slim container images) drops the file the package
    # installs: take it from the package archive itself.
    deb_dir="$(mktemp -d)"
    (cd "$deb_dir" && apt-get download libirrlicht-doc >&2) &&
      dpkg-deb --fsys-tarfile "$deb_dir"/libirrlicht-doc_*.deb |
      tar -xO ".$pk3gz" >"$deb_dir/map.pk3.gz" && pk3gz="$deb_dir/map.pk3.gz" ||
      { echo "bootstrap: $pk3gz is missing (package libirrlicht-doc)" >&2; exit 1; }
  fi
  python3 -c 'import gzip, io, sys, zipfile; open(sys.argv[2], "wb").write(zipfile.ZipFile(io.BytesIO(gzip.open(sys.argv[1]).read())).read("maps/20kdm2.bsp"))' \
    "$pk3gz" "$cache_dir/levels/20kdm2.bsp.tmp"
  mv "$cache_dir/levels/20kdm2.bsp.tmp" "$cache_dir/levels/20kdm2.bsp"
  echo "bootstrap: extracted 20kdm2.bsp into $cache_dir/levels" >&2
fi

# Release build into build/. Configure once; later runs only rebuild what changed.
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
# ccache (Debian) makes a rebuild in a fresh clone cheap; the build is the same without it.
command -v ccache >/dev/null && generator+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
if [ ! -f "$repo_root/build/CMakeCache.txt" ]; then
  cmake -S "$repo_root" -B "$repo_root/build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >&2
fi
cmake --build "$repo_root/build" --parallel "$(nproc)" >&2
