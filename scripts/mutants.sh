#!/usr/bin/env bash
# Mutation testing, one crate at a time, bounded for a small shared machine. Not run by CI.
#
#   scripts/mutants.sh              the math crate, every mutant (.cargo/mutants-math.toml)
#   scripts/mutants.sh render       raster, wall clipper and portal pass (.cargo/mutants-render.toml)
#   scripts/mutants.sh term         the frame encoder, its cursor and SGR modules (.cargo/mutants-term.toml)
#   scripts/mutants.sh walk         the walk's input and tap logic (.cargo/mutants-walk.toml)
#   scripts/mutants.sh math -- ARGS extra cargo-mutants arguments, e.g. `-f crates/math/src/clip.rs`,
#                                   `--re normal_matrix`, `--shard 1/4`
#
# Each scope builds and tests its own crate only (`-p`): a mutant of the math crate rebuilds the
# math crate and its tests, nothing above it.
#
# One mutant at a time (-j 1) under `nice`, in the test profile. Not `--copy-target`: the copy loses
# the files' times, so cargo rebuilds every dependency anyway (about 8 minutes on two busy cores,
# once per run, before the first mutant). Results go to target/mutants-<scope>/mutants.out
# (caught.txt, missed.txt, timeout.txt, unviable.txt); the exit status is cargo-mutants' own (0: no
# mutant missed). Record the score and every survivor's reason in MUTANTS.md.
#
# Time: each mutant rebuilds its crate and that crate's test binaries; MUTANTS.md has each scope's
# last run time. Shard (`--shard k/n`) to spread a long run.
# MUTANTS_TIME_LIMIT (seconds, default 0: none) stops the run after that long, keeping what finished;
# MUTANTS_OUT (default target/mutants-<scope>) is where the results go.
set -euo pipefail
cd "$(dirname "$0")/.."

scope="${1:-math}"
[ $# -gt 0 ] && shift
[ "${1:-}" = "--" ] && shift

case "$scope" in
  math | render | term | walk) config=.cargo/mutants-$scope.toml; package=mazewalk-$scope ;;
  *) echo "usage: $0 [math|render|term|walk] [-- cargo-mutants args]" >&2; exit 2 ;;
esac

if ! cargo mutants --version >/dev/null 2>&1; then
  cargo install --locked cargo-mutants
fi

# No debug info in the mutants' builds: linking the test binaries is most of a mutant's build time,
# and a failing test needs no backtrace to count as a catch.
export CARGO_PROFILE_TEST_DEBUG="${CARGO_PROFILE_TEST_DEBUG:-false}"

limit="${MUTANTS_TIME_LIMIT:-0}"
out="${MUTANTS_OUT:-target/mutants-$scope}" # another directory lets two shards run side by side
run=(nice cargo mutants --config "$config" -p "$package" -j 1 -o "$out" "$@")
if [ "$limit" -gt 0 ]; then
  # SIGINT lets cargo-mutants stop cleanly and write what it has.
  exec timeout --signal=INT --kill-after=60 "$limit" "${run[@]}"
else
  exec "${run[@]}"
fi
