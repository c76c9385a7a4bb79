#!/usr/bin/env bash
# Fuzzes the glTF loader (tests/fuzz/fuzz_gltf_loader.cpp) with libFuzzer for SECONDS (default
# 60). Installs what it needs beyond .ci/setup's packages if missing (Debian 12, as root), builds
# the target in build-fuzz/ (clang, ASan + UBSan, tinygltf compiled in), seeds the corpus
# from tests/data/*.gltf, tests/data/loader/* and a GLB made from the loader example, and runs.
# A finding fails the script and leaves its input in build-fuzz/findings/; the corpus grows in
# build-fuzz/corpus/ from run to run.
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds="${1:-60}"

# libclang-rt-dev: libclang_rt.fuzzer (-fsanitize=fuzzer); nlohmann-json3-dev and libstb-dev: to
# compile tinygltf and stb_image into the target (tinygltf_impl.cpp).
packages=(clang libclang-rt-dev nlohmann-json3-dev libstb-dev)
missing=()
for p in "${packages[@]}"; do
  if [ "$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null)" != "installed" ]; then
    missing+=("$p")
  fi
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "fuzz: installing ${missing[*]}" >&2
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
fi

cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Release \
  -DBRUME_SANITIZE=ON -DBRUME_FUZZ=ON -DBRUME_TESTS=OFF
cmake --build build-fuzz -j"$(nproc)" --target fuzz_gltf_loader

seeds=build-fuzz/seeds
rm -rf "$seeds"
mkdir -p "$seeds" build-fuzz/corpus build-fuzz/findings
cp tests/data/*.gltf tests/data/loader/* "$seeds"/
python3 tests/fuzz/glb_seed.py tests/data/loader/example.gltf "$seeds/example.glb"

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
build-fuzz/fuzz_gltf_loader -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -dict=tests/fuzz/gltf.dict -artifact_prefix=build-fuzz/findings/ -print_final_stats=1 \
  build-fuzz/corpus "$seeds" </dev/null
