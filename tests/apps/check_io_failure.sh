#!/bin/sh
# I/O failures of rubcont as a user meets them, with the real executable and a real file system.
#   tests/apps/check_io_failure.sh RUBCONT CASE     (from the repository root)
# CASE: full_disk (a 2 MB tmpfs, filled but for 200 kB), size_limit (ulimit -f), read_only (a
# read-only tmpfs, or a directory without write permission; and a directory that cannot be made),
# directory (a directory where the file should be), lock_held (another process holds the HDF5 lock
# of a file to read; a lock on the file to write does not stop the run), two_writers (two runs
# write one output at once, HDF5 file locking on and off).
# Each failure must end with exit 1 and one line on stderr naming the file and the system's reason,
# the older result under the real name intact and no temporary left. Exit 0 pass, 1 fail, 77 the
# case cannot be set up here (the reason on stdout; ctest shows it as skipped).
# The tmpfs cases mount in a user and mount namespace of their own (unshare -r -m), where the script
# runs itself again with CASE-inside.
set -u
rubcont=$(realpath "$1")
case=$2
scene=$(pwd)/scenes/thesis_A_a.toml
other=$(pwd)/scenes/thesis_B_b.toml
export RUBCONT_PYTHON=/nonexistent/python3  # no figures
work=${CHECK_IO_WORK:-$(mktemp -d)}
[ -n "${CHECK_IO_WORK:-}" ] || trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL ($case): $*"; [ -f "$work/err" ] && sed 's/^/  stderr: /' "$work/err"; exit 1; }
skip() { echo "SKIPPED ($case): $*"; exit 77; }

# expect_io_error RC FILE REASON: exit code 1, stderr one line naming FILE and REASON (a regex).
expect_io_error() {
  [ "$1" = 1 ] || fail "exit code $1, expected 1"
  [ "$(wc -l <"$work/err")" = 1 ] || fail "stderr has $(wc -l <"$work/err") lines, expected 1"
  grep -Eq "^rubcont: error: cannot (write|read) $2: ($3)\$" "$work/err" ||
    fail "stderr does not name $2 and the reason ($3)"
}

# expect_only DIR NAMES...: DIR holds exactly NAMES (no temporary left).
expect_only() {
  dir=$1; shift
  [ "$(ls -A "$dir" | sort | tr '\n' ' ')" = "$(printf '%s\n' "$@" | sort | tr '\n' ' ')" ] ||
    fail "$dir holds: $(ls -A "$dir" | tr '\n' ' '), expected: $*"
}

# older FILE: an analytic result as the older file, with a copy to compare against.
older() {
  "$rubcont" analytic "$scene" --quiet --out "$1" >/dev/null 2>"$work/err" || fail "the older result"
  cp "$1" "$work/before.h5"
}

in_namespace() {
  unshare -r -m true 2>/dev/null || skip "no user and mount namespace here (unshare -r -m)"
  mkdir -p "$work/fs"
  CHECK_IO_WORK=$work unshare -r -m "$0" "$1" "$case-inside"
  exit $?
}

case $case in
  full_disk) in_namespace "$1" ;;
  full_disk-inside)
    mount -t tmpfs -o size=2m none "$work/fs" || skip "tmpfs cannot be mounted"
    older "$work/fs/a.h5"
    # Fills the file system but for 200 kB: the run starts and its write fails partway.
    dd if=/dev/zero of="$work/fs/filler" bs=4k 2>/dev/null
    truncate -s -200k "$work/fs/filler"
    "$rubcont" branches "$scene" --quiet --out "$work/fs/a.h5" >/dev/null 2>"$work/err"
    expect_io_error $? "$work/fs/a.h5" "No space left on device"
    cmp -s "$work/fs/a.h5" "$work/before.h5" || fail "the older result changed"
    expect_only "$work/fs" a.h5 filler ;;
  size_limit)
    mkdir "$work/out"
    older "$work/out/a.h5"
    # rubcont ignores SIGXFSZ itself: the write past the limit fails with EFBIG.
    (ulimit -f 100 && exec "$rubcont" branches "$scene" --quiet --out "$work/out/a.h5") \
      >/dev/null 2>"$work/err"
    expect_io_error $? "$work/out/a.h5" "File too large"
    cmp -s "$work/out/a.h5" "$work/before.h5" || fail "the older result changed"
    expect_only "$work/out" a.h5 ;;
  read_only)
    if [ "$(id -u)" != 0 ]; then  # permissions stop a user (root passes them)
      mkdir "$work/fs"
      older "$work/fs/a.h5"
      chmod 555 "$work/fs"
      reason="Permission denied"
    else
      in_namespace "$1"
    fi ;;
  read_only-inside)
    mount -t tmpfs -o size=1m none "$work/fs" || skip "tmpfs cannot be mounted"
    older "$work/fs/a.h5"
    mount -o remount,ro "$work/fs" || skip "the tmpfs cannot be made read-only"
    reason="Read-only file system" ;;
  directory)
    mkdir -p "$work/out/a.h5/inside"
    "$rubcont" branches "$scene" --quiet --out "$work/out/a.h5" >/dev/null 2>"$work/err"
    expect_io_error $? "$work/out/a.h5" "Is a directory"
    expect_only "$work/out" a.h5
    expect_only "$work/out/a.h5" inside
    # A study finds it before its work (a loop of A(a) takes minutes).
    timeout 30 "$rubcont" loop "$scene" --quiet --out "$work/out/a.h5" >/dev/null 2>"$work/err"
    expect_io_error $? "$work/out/a.h5" "Is a directory" ;;
  lock_held)
    [ "${HDF5_USE_FILE_LOCKING:-TRUE}" != FALSE ] || skip "HDF5_USE_FILE_LOCKING=FALSE"
    command -v flock >/dev/null || skip "no flock(1)"
    mkdir "$work/out"
    older "$work/out/a.h5"
    # A checkpoint that another process holds (HDF5 takes flock locks): --resume must read it.
    cp "$work/out/a.h5" "$work/out/a.up.checkpoint.h5"
    flock -o -x "$work/out/a.up.checkpoint.h5" sleep 10 >/dev/null 2>&1 &
    holder=$!
    sleep 0.2
    "$rubcont" sweep "$scene" --direction up --resume --quiet --out "$work/out/a.h5" >/dev/null \
      2>"$work/err"
    rc=$?
    expect_io_error $rc "$work/out/a.up.checkpoint.h5" "unable to lock file, errno = 11, .*"
    cmp -s "$work/out/a.h5" "$work/before.h5" || fail "the older result changed"
    # Writing needs no lock: a reader holding the result keeps its open file, the run replaces it.
    flock -o -x "$work/out/a.h5" sleep 10 >/dev/null 2>&1 &
    reader=$!
    sleep 0.2
    "$rubcont" branches "$scene" --quiet --out "$work/out/a.h5" >/dev/null 2>"$work/err" ||
      fail "a write under a reader's lock failed"
    kill "$holder" "$reader"
    expect_only "$work/out" a.h5 a.up.checkpoint.h5 ;;
  two_writers)
    # An analytic result's bytes are the same on every run (no timestamps): the output must be
    # one of the two files each scene gives alone, byte for byte.
    mkdir "$work/out"
    "$rubcont" analytic "$scene" --quiet --out "$work/a.h5" >/dev/null 2>&1 || fail "reference a"
    "$rubcont" analytic "$other" --quiet --out "$work/b.h5" >/dev/null 2>&1 || fail "reference b"
    for locking in TRUE FALSE; do
      for trial in 1 2 3; do
        HDF5_USE_FILE_LOCKING=$locking "$rubcont" analytic "$scene" --quiet --out "$work/out/x.h5" \
          >/dev/null 2>"$work/err_a" &
        first=$!
        HDF5_USE_FILE_LOCKING=$locking "$rubcont" analytic "$other" --quiet --out "$work/out/x.h5" \
          >/dev/null 2>"$work/err_b"
        rc_b=$?
        wait "$first"
        rc_a=$?
        # Each run either wrote its file whole (exit 0) or says why not (exit 1, one line).
        for run in a b; do
          eval rc=\$rc_$run
          [ "$rc" = 0 ] || { cp "$work/err_$run" "$work/err"; expect_io_error "$rc" "$work/out/x.h5" ".*"; }
        done
        cmp -s "$work/a.h5" "$work/out/x.h5" || cmp -s "$work/b.h5" "$work/out/x.h5" ||
          fail "locking $locking, trial $trial: the output is neither run's whole file (exits $rc_a, $rc_b)"
        expect_only "$work/out" x.h5
        rm "$work/out/x.h5"
      done
    done ;;
  *) echo "unknown case $case"; exit 2 ;;
esac

case $case in
  read_only|read_only-inside)
    "$rubcont" branches "$scene" --quiet --out "$work/fs/a.h5" >/dev/null 2>"$work/err"
    expect_io_error $? "$work/fs/a.h5" "$reason"
    cmp -s "$work/fs/a.h5" "$work/before.h5" || fail "the older result changed"
    expect_only "$work/fs" a.h5
    # A missing directory that cannot be made: the same, before any work.
    "$rubcont" branches "$scene" --quiet --out "$work/fs/new/a.h5" >/dev/null 2>"$work/err"
    expect_io_error $? "$work/fs/new/a.h5" "$reason"
    [ "$(id -u)" = 0 ] || chmod 755 "$work/fs" ;;
esac
echo "PASS ($case)"
