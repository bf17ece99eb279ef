#!/bin/bash
# Never destroy what is not ours: what the tools' output path (tools/cli.c,
# cli_output: every -o of every tool, and cli_mesh_write) does to every kind
# of destination. Each check here failed before the destination rules:
#  - a device (/dev/null, /dev/full: made here with mknod, so a regression
#    never replaces the machine's own), a FIFO, a symbolic link to one: written
#    through, still the same kind of file afterwards; ENOSPC is an error;
#  - a symbolic link to a regular file stays a link, its target is replaced;
#  - a replaced file keeps its mode (0640 stays 0640);
#  - a file the user may not write is refused as cp refuses it (run as
#    nobody through setpriv when we are root);
#  - a dangling symbolic link and a directory are refused;
#  - a 255-byte name works (the temporary name is shortened to fit NAME_MAX);
#  - SIGINT, SIGTERM and SIGHUP remove the temporary file; SIGKILL leaves one
#    named .NAME.XXXXXXXX.geomtmp (the documented pattern), never NAME.
# Usage: test_output_safety.sh GEOM-BARY GEOM-CONVERT DATA_DIR
set -u
BARY=$1
CONVERT=$2
DATA=$3
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-output-safety.XXXXXX") || exit 1
chmod 755 "$T"
trap 'rm -rf "$T"' EXIT
failures=0
checks=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
check() { # check WHAT COMMAND...
    local what=$1; shift
    checks=$((checks + 1))
    "$@" || fail "$what"
}
no_temps() { # no_temps DIR: no temporary file left behind
    local left
    left=$(find "$1" -maxdepth 1 -name '*.geomtmp' | head -3)
    [ -z "$left" ] || { echo "left behind: $left" >&2; return 1; }
}
stale_named() { # the temporary's name follows the documented pattern
    ls -A "$1" | grep -Eq '^\.out\.txt\.[a-z0-9]{8}\.geomtmp$'
}
POINT="0 0 0  1 0 0  0 1 0  0.25 0.25 0"

# --- a new file, and the mode of a replaced one
( umask 022; echo "$POINT" | "$BARY" -o "$T/new.txt" )
check "new file written" grep -q . "$T/new.txt"
check "new file mode 0644 under umask 022" [ "$(stat -c %a "$T/new.txt")" = 644 ]
echo old >"$T/mode.txt"; chmod 640 "$T/mode.txt"
echo "$POINT" | "$BARY" -o "$T/mode.txt"
check "replaced file keeps mode 0640" [ "$(stat -c %a "$T/mode.txt")" = 640 ]
check "replaced file has the new content" grep -qv old "$T/mode.txt"
"$CONVERT" "$DATA/tetra.off" "$T/mode.obj" && chmod 600 "$T/mode.obj" &&
    "$CONVERT" "$DATA/tetra.off" "$T/mode.obj"
check "geom-convert keeps mode 0600" [ "$(stat -c %a "$T/mode.obj")" = 600 ]
check "no temporaries after success" no_temps "$T"

# --- a symbolic link to a regular file stays a link
echo old >"$T/target.txt"; ln -s target.txt "$T/link.txt"
echo "$POINT" | "$BARY" -o "$T/link.txt"
check "symlink still a symlink" [ -L "$T/link.txt" ]
check "symlink target replaced" grep -qv old "$T/target.txt"
ln -s target.obj "$T/link.obj"; echo old >"$T/target.obj"
"$CONVERT" "$DATA/tetra.off" "$T/link.obj"
check "geom-convert: symlink still a symlink" [ -L "$T/link.obj" ]
check "geom-convert: symlink target replaced" grep -q '^v ' "$T/target.obj"

# --- devices: written through, never replaced
if mknod "$T/null" c 1 3 2>/dev/null && mknod "$T/full" c 1 7 2>/dev/null; then
    echo "$POINT" | "$BARY" -o "$T/null"; rc=$?
    check "write to a null device succeeds" [ $rc -eq 0 ]
    check "null device still a character device" [ -c "$T/null" ]
    "$CONVERT" "$DATA/tetra.off" "$T/null" --format obj; rc=$?
    check "geom-convert to a null device succeeds" [ $rc -eq 0 ]
    check "geom-convert: null device still a device" [ -c "$T/null" ]
    ln -s null "$T/null-link"
    echo "$POINT" | "$BARY" -o "$T/null-link"
    check "symlink to a device still a symlink" [ -L "$T/null-link" ]
    check "device behind the symlink still a device" [ -c "$T/null" ]
    echo "$POINT" | "$BARY" -o "$T/full" 2>"$T/err"; rc=$?
    check "ENOSPC is an error (exit 1)" [ $rc -eq 1 ]
    check "ENOSPC is named" grep -q "No space left" "$T/err"
    check "full device still a character device" [ -c "$T/full" ]
    "$CONVERT" "$DATA/tetra.off" "$T/full" --format ply 2>"$T/err"; rc=$?
    check "geom-convert: ENOSPC is an error" [ $rc -eq 1 ]
    check "geom-convert: full device still a device" [ -c "$T/full" ]
    check "no temporaries next to devices" no_temps "$T"
else
    echo "note: mknod not permitted; device checks skipped" >&2
fi

# --- a FIFO: written through
mkfifo "$T/fifo"
timeout 20 cat "$T/fifo" >"$T/fifo.out" &
reader=$!
echo "$POINT" | "$BARY" -o "$T/fifo"; rc=$?
wait $reader
check "write to a FIFO succeeds" [ $rc -eq 0 ]
check "FIFO still a FIFO" [ -p "$T/fifo" ]
check "FIFO reader got the output" grep -q . "$T/fifo.out"

# --- refused destinations
mkdir "$T/dir"
echo "$POINT" | "$BARY" -o "$T/dir" 2>"$T/err"; rc=$?
check "directory refused" [ $rc -eq 1 ]
check "directory named" grep -qi "directory" "$T/err"
ln -s nowhere.txt "$T/dangling"
echo "$POINT" | "$BARY" -o "$T/dangling" 2>"$T/err"; rc=$?
check "dangling symlink refused" [ $rc -eq 1 ]
check "dangling symlink not followed" [ ! -e "$T/nowhere.txt" ]
check "dangling symlink still a symlink" [ -L "$T/dangling" ]
if [ "$(id -u)" -ne 0 ] || command -v setpriv >/dev/null; then
    AS=()
    [ "$(id -u)" -ne 0 ] || AS=(setpriv --reuid=65534 --regid=65534 --clear-groups)
    mkdir "$T/ro"; chmod 777 "$T/ro"
    echo keep >"$T/ro/file.txt"; chmod 444 "$T/ro/file.txt"
    echo "$POINT" | "${AS[@]}" "$BARY" -o "$T/ro/file.txt" 2>"$T/err"; rc=$?
    check "read-only file refused (exit 1)" [ $rc -eq 1 ]
    check "read-only file refused: permission named" grep -q "Permission denied" "$T/err"
    check "read-only file untouched" [ "$(cat "$T/ro/file.txt")" = keep ]
    check "no temporaries next to the read-only file" no_temps "$T/ro"
fi

# --- NAME_MAX
long=$(printf 'n%.0s' $(seq 1 251)).obj
"$CONVERT" "$DATA/tetra.off" "$T/$long"; rc=$?
check "255-byte output name works" [ $rc -eq 0 ]
check "255-byte output written" [ -s "$T/$long" ]
long=$(printf 'n%.0s' $(seq 1 251)).txt
echo "$POINT" | "$BARY" -o "$T/$long"; rc=$?
check "255-byte output name works (geom-bary)" [ $rc -eq 0 ]
check "no temporaries after long names" no_temps "$T"

# --- signals: the temporary file goes with the process
for sig in INT TERM HUP KILL; do
    d="$T/sig-$sig"; mkdir "$d"; mkfifo "$d/in"
    # geom-bary opens its output, then reads the FIFO, which we hold open.
    # (bash starts background jobs with SIGINT ignored: restore the default)
    env --default-signal=INT "$BARY" -o "$d/out.txt" "$d/in" &
    pid=$!
    exec 7>"$d/in"
    echo "$POINT" >&7
    for _ in $(seq 1 50); do
        [ -n "$(find "$d" -name '*.geomtmp')" ] && break
        sleep 0.1
    done
    check "SIG$sig: temporary file exists while running" [ -n "$(find "$d" -name '.out.txt.*.geomtmp')" ]
    kill -s "$sig" $pid
    wait $pid 2>/dev/null; rc=$?
    exec 7>&-
    check "SIG$sig: the tool died of the signal (status $rc)" [ $rc -gt 128 ]
    check "SIG$sig: no output file" [ ! -e "$d/out.txt" ]
    if [ "$sig" = KILL ]; then
        check "SIGKILL: the stale temporary matches .NAME.XXXXXXXX.geomtmp" \
            stale_named "$d"
    else
        check "SIG$sig: temporary removed" no_temps "$d"
    fi
done

echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
