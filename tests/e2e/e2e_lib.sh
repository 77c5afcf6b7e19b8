# Shared by the end-to-end scripts (sourced after `set -euo pipefail`).

# e2e_begin NAME HANDSCAN_BIN WORK_DIR: sets $bin and $work (emptied) and names the script's failures.
e2e_begin() {
  e2e_name=$1
  bin=$2
  work=$3
  rm -rf "$work"
  mkdir -p "$work"
}
fail() { echo "$e2e_name: FAIL: $*" >&2; exit 1; }

# eval_rmse FILE PATTERN: the number after `rmse` on the first line of `handscan eval`'s output
# that matches PATTERN (e.g. '^ATE', '^rotation error').
eval_rmse() { awk -v pat="$2" '$0 ~ pat {for (i = 1; i <= NF; ++i) if ($i == "rmse") {print $(i + 1); exit}}' "$1"; }

# at_most VALUE LIMIT: true when the decimal VALUE is at most LIMIT.
at_most() { awk -v v="$1" -v m="$2" 'BEGIN { exit !(v <= m) }'; }
