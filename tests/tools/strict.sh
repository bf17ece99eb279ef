# The prologue of the tool tests that stop at their first failure (testlib.sh
# is for those that count checks). Source it first, with the script's
# arguments (the tool, then the data directory):
#   . "$(dirname "$0")/strict.sh" "$@"
# It sets -euo pipefail, tool and data from the arguments, py (a Python with
# numpy: $PYTHON3 or /usr/bin/python3), tmp (a scratch directory removed on
# exit) and fail MESSAGE (prints "FAIL: MESSAGE" and exits 1).
set -euo pipefail
tool=$1
data=$2
py=${PYTHON3:-/usr/bin/python3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
