#!/usr/bin/env bash
# Cold `cargo test` wall time of two commits, measured alternately in one run (A B A B …) on fresh
# clones, so that both see the same machine and the same load:
#
#   scripts/cold_test_time.sh BEFORE AFTER [ROUNDS]      e.g. scripts/cold_test_time.sh f2f7b5f main 2
#
# Each round clones each commit into a new directory (nothing of the working tree, no target/), with
# the course files placed beside a clone that still reads them from ../shared/mazes-cs559 (commits
# from before the repository kept its own copy), then times the README's test command of that
# commit from scratch (dependencies compiled, tests run): `scripts/test-all --locked` where the commit
# has it (cargo-nextest, when installed, runs the test binaries in parallel), else `cargo test --locked`. The crates' sources come from cargo's registry cache, which
# the first round fills; the printed line per run is: commit, round, wall seconds, exit status.
# Not run by CI (a round takes several minutes on two cores).
set -euo pipefail
cd "$(dirname "$0")/.."

before="${1:?usage: $0 BEFORE AFTER [ROUNDS]}"
after="${2:?usage: $0 BEFORE AFTER [ROUNDS]}"
rounds="${3:-2}"
repo="$(pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# What the clones of old commits read from beside the repository.
mkdir -p "$work/shared/mazes-cs559"
cp mazes/cs559/*.maze mazes/cs559/README.md "$work/shared/mazes-cs559/"

export CARGO_INCREMENTAL=0 CARGO_TERM_COLOR=never
for round in $(seq "$rounds"); do
  for commit in "$before" "$after"; do
    dir="$work/clone"
    rm -rf "$dir"
    git clone -q "$repo" "$dir"
    git -C "$dir" checkout -q "$commit"
    # Fetch outside the clock: the measure is building and testing, not downloading.
    (cd "$dir" && cargo fetch --locked -q)
    start=$(date +%s.%N)
    status=0
    if [ -x "$dir/scripts/test-all" ]; then
      (cd "$dir" && scripts/test-all --locked >"$work/log" 2>&1) || status=$?
    else
      (cd "$dir" && cargo test --locked -q >"$work/log" 2>&1) || status=$?
    fi
    end=$(date +%s.%N)
    printf '%s\tround %s\t%.1f s\texit %s\n' "$commit" "$round" "$(echo "$end - $start" | bc)" "$status"
    if [ "$status" -ne 0 ]; then tail -n 30 "$work/log" >&2; fi
  done
done
