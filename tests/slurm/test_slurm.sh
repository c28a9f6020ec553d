#!/usr/bin/env bash
# test_slurm.sh — end-to-end check of scripts/slurm/render.sh on a live Slurm
# cluster: a tiny rope scene is simulated, rendered as 3 chunks by a job array
# and joined, and the film is checked with `reel info --video`.
#
#   tests/slurm/test_slurm.sh REEL_BINARY REPO_ROOT
#
# Exit status (ctest conventions): 0 pass, 1 fail, 77 skipped when no Slurm
# cluster answers here (register with SKIP_RETURN_CODE 77). The binary, the
# repository and the temp dir must be visible to the compute nodes, which is
# the case on the single node of scripts/slurm/setup-single-node.sh.
set -euo pipefail

if (($# != 2)); then
  echo "usage: $0 REEL_BINARY REPO_ROOT" >&2
  exit 1
fi

skip() {
  echo "skipped: no Slurm cluster answers here (scripts/slurm/setup-single-node.sh starts a single-node one)"
  exit 77
}
fail() {
  echo "FAIL: $*" >&2
  [[ -z ${tmp:-} ]] || echo "(kept $tmp for inspection)" >&2
  exit 1
}

# ---- is there a cluster? ---------------------------------------------------
command -v sbatch >/dev/null 2>&1 || skip
command -v sinfo >/dev/null 2>&1 || skip
states=$(timeout 10 sinfo -h -o %T 2>/dev/null) || skip
# A node that can take jobs now or soon; "idle*" (not responding) won't do.
grep -Eq '^(idle|mixed|allocated)$' <<<"$states" || skip

reel=$(realpath "$1")
repo=$(realpath "$2")
render_sh=$repo/scripts/slurm/render.sh
[[ -x $reel ]] || fail "reel binary '$reel' not found or not executable"
[[ -x $render_sh ]] || fail "$render_sh not found or not executable"

# ---- the scene -------------------------------------------------------------
tmp=$(mktemp -d "${TMPDIR:-/tmp}/reel-slurm-test.XXXXXX")
cat >"$tmp/scene.json" <<'EOF'
{"format": "reel/1", "name": "farm_test", "fps": 10, "duration": 1.2, "render": {"width": 96, "height": 64, "samples": 1}, "camera": {"position": [0, 1, 3], "target": [0, 0, 0]}, "bodies": [{"type": "rope", "name": "r", "start": [-0.5, 0.5, 0], "end": [0.5, 0.5, 0], "segments": 8, "stiffness": 400, "pinned": ["start"]}]}
EOF

# ---- render on the farm ----------------------------------------------------
echo "submitting: $render_sh $tmp/scene.json --chunks 3 ..."
if ! timeout 600 "$render_sh" "$tmp/scene.json" --chunks 3 -o "$tmp/film.mp4" \
      --cache "$tmp/cache" --reel "$reel" --wait; then
  fail "render.sh did not make the film (its output above says which stage failed)"
fi

# ---- check the result ------------------------------------------------------
[[ -s $tmp/film.mp4 ]] || fail "$tmp/film.mp4 is missing or empty"

shopt -s nullglob
chunks=("$tmp"/cache/chunks/chunk_*.mp4)
shopt -u nullglob
((${#chunks[@]} == 3)) || fail "expected 3 chunk files in $tmp/cache/chunks, found ${#chunks[@]}"
for c in "${chunks[@]}"; do
  [[ -s $c ]] || fail "chunk $c is empty"
done

info=$("$reel" info --video "$tmp/film.mp4") || fail "reel info --video $tmp/film.mp4 failed"
echo "reel info --video: $info"
# One JSON line: take integer fields with a pattern rather than need jq.
field() { sed -n "s/.*\"$1\"[[:space:]]*:[[:space:]]*\([0-9][0-9]*\).*/\1/p" <<<"$info"; }
frames=$(field frames)
width=$(field width)
# A film has round(duration * fps) frames (Scene::frameCount in
# src/core/scene.h): at fps 10 over 1.2 s, frames t = 0, 0.1, ..., 1.1, 12 of them.
[[ $frames == 12 ]] || fail "expected 12 frames, reel info says '${frames:-?}'"
[[ $width == 96 ]] || fail "expected width 96, reel info says '${width:-?}'"

rm -rf "$tmp"
echo "ok: 3 chunks rendered on Slurm, joined into 12 frames of width 96"
