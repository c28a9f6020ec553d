#!/usr/bin/env bash
# Runs reel's libFuzzer targets one after another (docs/fuzzing.md), each for SECONDS (default
# 600), from the fuzz preset's build: seeds are written by each target itself (REEL_FUZZ_SEEDS),
# the corpus grows in build/fuzz/corpus/TARGET, findings land in build/fuzz/findings/.
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]   (targets: scene mesh robot environment cache join suite)
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-600}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene mesh robot environment cache join suite)
bin=build/fuzz/tests/fuzz
[ -x "$bin/fuzz_scene" ] || { echo "fuzz.sh: build the fuzz preset first: cmake --preset fuzz && cmake --build --preset fuzz" >&2; exit 2; }
mkdir -p build/fuzz/findings build/fuzz/logs
for t in "${targets[@]}"; do
  exe="$bin/fuzz_$t"
  [ -x "$exe" ] || { echo "fuzz.sh: no target fuzz_$t" >&2; exit 2; }
  corpus=build/fuzz/corpus/$t seeds=build/fuzz/seeds/$t
  mkdir -p "$corpus" "$seeds"
  extra=()
  case $t in
    scene) ;;
    mesh) python3 tests/fuzz/make_mesh_seeds.py "$seeds"; extra=(-dict=tests/fuzz/mesh.dict -timeout=30) ;;
    *) REEL_FUZZ_SEEDS="$seeds" "$exe" >/dev/null 2>&1; extra=(-timeout=30) ;;
  esac
  # The scene target resolves its seeds' mesh paths from scenes/.
  if [ "$t" = scene ]; then
    (cd scenes && "../$exe" -max_total_time="$secs" -rss_limit_mb=4096 -max_len=65536 -close_fd_mask=2 \
       -dict=../tests/fuzz/scene.dict -timeout=20 -artifact_prefix=../build/fuzz/findings/ \
       "../$corpus" . ../tests/scenes) > "build/fuzz/logs/$t.log" 2>&1 || true
  else
    "$exe" -max_total_time="$secs" -rss_limit_mb=4096 -max_len=262144 -close_fd_mask=2 "${extra[@]}" \
      -artifact_prefix=build/fuzz/findings/"$t"- "$corpus" "$seeds" > "build/fuzz/logs/$t.log" 2>&1 || true
  fi
  echo "fuzz_$t: $(grep -E '^(Done|#[0-9]+ +DONE)' "build/fuzz/logs/$t.log" | tail -n 1) $(grep -cE '^==[0-9]+==ERROR|deadly signal|Test unit written' "build/fuzz/logs/$t.log") findings (build/fuzz/logs/$t.log)"
done
