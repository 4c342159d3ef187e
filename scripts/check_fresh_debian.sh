#!/usr/bin/env bash
# The README's two commands on a fresh Debian 12, as a newcomer meets them: a minimal Debian 12
# root made by debootstrap from Debian's repositories only, a clean clone of this checkout's HEAD
# copied in, then `scripts/bootstrap.sh run` and `scripts/bootstrap.sh test` run in it as root
# (scripts/setup.sh installs everything they need from Debian, and viewer/'s npm packages). Prints
# what passed and where the logs are (docs/ci.md, "A fresh Debian 12 root").
#
#   sudo scripts/check_fresh_debian.sh [--root DIR] [--mirror URL] [--security URL] [--reuse]
#                                      [--host-ca] [setup] [run] [test]
#
#   --root DIR      where the Debian 12 root goes (default /var/tmp/corridorsim-fresh-debian);
#                   it must not exist, unless --reuse
#   --mirror URL    the Debian mirror (default: the first one this machine's apt sources name)
#   --security URL  the security mirror (default: the one this machine's apt sources name)
#   --reuse         keep an existing root made by this script (skips debootstrap; packages that
#                   setup.sh installed there stay, so only a root without them is "fresh")
#   --host-ca       copy this machine's local CA certificates (/usr/local/share/ca-certificates)
#                   into the root: for networks whose HTTPS goes through an inspecting proxy,
#                   which npm's registry must be reached through
#   run test        which README commands to run, in that order (default: both)
#   setup           only scripts/setup.sh (the packages and viewer/'s npm ci; no build): quick
#
# The clone is of HEAD: commit what you want checked. The root's build uses CORRIDORSIM_JOBS (as
# bootstrap.sh does; default: every core) and takes the time of a cold build and the whole suite
# (about 45 minutes on two cores). The root stays for inspection; remove it with
# `rm -rf --one-file-system DIR` once nothing is mounted under it (this script unmounts on exit).
# Exit 0: every command passed; 1: one failed (its log's end is printed); 2: bad usage.
set -euo pipefail
src="$(cd "$(dirname "$0")/.." && pwd)"

root=/var/tmp/corridorsim-fresh-debian
# The mirrors default to those of this machine's own apt sources (deb822 .sources files or the
# one-line sources.list form): the root reaches Debian the way this machine does.
apt_uris() {  # every URI the machine's apt sources name, one a line
  cat /etc/apt/sources.list.d/*.sources 2>/dev/null | sed -n 's/^URIs:[[:space:]]*//p' | tr ' ' '\n'
  cat /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null |
    sed -n 's/^deb[[:space:]]\+\(\[[^]]*\][[:space:]]\+\)\?\([^[:space:]]\+\).*/\2/p'
}
mirror="$(apt_uris | grep -v -- '-security' | head -n 1 || true)"
security="$(apt_uris | grep -- '-security' | head -n 1 || true)"
reuse=0
host_ca=0
commands=()
usage() {
  echo "check_fresh_debian: $1 (usage: scripts/check_fresh_debian.sh [--root DIR] [--mirror URL]" \
       "[--security URL] [--reuse] [--host-ca] [setup] [run] [test]; the script's header says more)" >&2
  exit 2
}
while [ $# -gt 0 ]; do
  case "$1" in
    --root) [ $# -ge 2 ] || usage "--root needs a folder"; root="$2"; shift 2 ;;
    --mirror) [ $# -ge 2 ] || usage "--mirror needs a URL"; mirror="$2"; shift 2 ;;
    --security) [ $# -ge 2 ] || usage "--security needs a URL"; security="$2"; shift 2 ;;
    --reuse) reuse=1; shift ;;
    --host-ca) host_ca=1; shift ;;
    setup|run|test) commands+=("$1"); shift ;;
    *) usage "unexpected argument '$1'" ;;
  esac
done
[ ${#commands[@]} -gt 0 ] || commands=(run test)
[ -n "$mirror" ] || usage "this machine's apt sources name no Debian mirror: pass --mirror URL"
case "$root" in /*) ;; *) usage "--root must be an absolute path (got '$root')" ;; esac
[ "$root" != / ] || usage "--root must not be /"
if [ "$(id -u)" -ne 0 ]; then
  echo "check_fresh_debian: needs root (debootstrap, chroot, mounts): run it with sudo" >&2
  exit 2
fi
if [ -e "$root" ] && [ "$reuse" -eq 0 ]; then
  usage "$root exists: pass --reuse to use the root made there before, or remove it"
fi
if [ "$reuse" -eq 1 ] && [ -e "$root" ] && [ ! -f "$root/etc/corridorsim-fresh-debian" ]; then
  usage "$root was not made by this script (no etc/corridorsim-fresh-debian): refusing to reuse it"
fi
for tool in git chroot mount; do
  command -v "$tool" > /dev/null || { echo "check_fresh_debian: needs $tool" >&2; exit 2; }
done
if ! command -v debootstrap > /dev/null; then
  echo "check_fresh_debian: installing debootstrap"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap
fi

start=$SECONDS
if [ ! -f "$root/etc/corridorsim-fresh-debian" ]; then
  echo "check_fresh_debian: debootstrap --variant=minbase bookworm $root $mirror"
  mkdir -p "$root"
  debootstrap --variant=minbase bookworm "$root" "$mirror" > "$root.debootstrap.log" 2>&1 || {
    tail -n 20 "$root.debootstrap.log" >&2; echo "check_fresh_debian: debootstrap failed ($root.debootstrap.log)" >&2; exit 1; }
  cat > "$root/etc/apt/sources.list" <<EOF
deb $mirror bookworm main
deb $mirror bookworm-updates main
${security:+deb $security bookworm-security main}
EOF
  echo "made by corridorsim's scripts/check_fresh_debian.sh" > "$root/etc/corridorsim-fresh-debian"
  echo "check_fresh_debian: root made in $((SECONDS - start)) s"
fi
if [ "$host_ca" -eq 1 ]; then
  mkdir -p "$root/usr/local/share/ca-certificates"
  cp /usr/local/share/ca-certificates/*.crt "$root/usr/local/share/ca-certificates/" 2>/dev/null || true
  # installed with ca-certificates (npm depends on it); a reused root takes them now
  if [ -x "$root/usr/sbin/update-ca-certificates" ]; then chroot "$root" update-ca-certificates > /dev/null; fi
fi
cp /etc/resolv.conf "$root/etc/resolv.conf"

cleanup() {
  for m in dev sys proc; do
    if mountpoint -q "$root/$m"; then umount -R "$root/$m" || umount -R -l "$root/$m" || true; fi
  done
}
trap cleanup EXIT
mountpoint -q "$root/proc" || mount -t proc proc "$root/proc"
# /sys with what is mounted under it (the cgroup file system: slurmd needs it, as on a machine)
if ! mountpoint -q "$root/sys"; then mount --rbind /sys "$root/sys"; mount --make-rslave "$root/sys"; fi
if ! mountpoint -q "$root/dev"; then mount --rbind /dev "$root/dev"; mount --make-rslave "$root/dev"; fi

# A clean clone of HEAD (no build tree, no node_modules, no untracked files).
rm -rf --one-file-system "$root/root/corridorsim"
git clone --quiet --no-hardlinks "$src" "$root/root/corridorsim"
echo "check_fresh_debian: cloned $(git -C "$src" rev-parse --short HEAD) into $root/root/corridorsim"

failed=0
summary=()
for c in "${commands[@]}"; do
  log="$root/root/bootstrap_$c.log"
  script="scripts/bootstrap.sh $c"
  if [ "$c" = setup ]; then script=scripts/setup.sh; fi
  echo "check_fresh_debian: $script (log $log)"
  t0=$SECONDS rc=0
  chroot "$root" /usr/bin/env -i HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    LANG=C.UTF-8 ${CORRIDORSIM_JOBS:+CORRIDORSIM_JOBS=$CORRIDORSIM_JOBS} \
    /bin/bash -c "cd /root/corridorsim && $script" > "$log" 2>&1 || rc=$?
  line="$script: exit $rc in $((SECONDS - t0)) s"
  if [ "$c" = test ]; then
    line="$line; $(grep -E 'tests passed, [0-9]+ tests? failed out of' "$log" | tail -n 1 || true)"
  fi
  summary+=("$line")
  if [ "$rc" -ne 0 ]; then
    failed=1
    echo "check_fresh_debian: $script FAILED; the end of its log:" >&2
    tail -n 40 "$log" >&2
  fi
done
echo "check_fresh_debian: on $(cat "$root/etc/debian_version") with node $(chroot "$root" node --version 2>/dev/null || echo none), $(chroot "$root" chromium --version 2>/dev/null | head -n 1 || echo 'no chromium'):"
for s in "${summary[@]}"; do echo "  $s"; done
exit "$failed"
