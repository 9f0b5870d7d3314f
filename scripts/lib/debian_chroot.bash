# SPDX-License-Identifier: BSD-3-Clause
# Sourced by scripts/check-fresh-machine and scripts/check-arm64: a bare Debian 12 (debootstrap minbase + git) in
# a chroot, its base system cached as a tarball so that a second run starts in seconds, and commands run in it
# inside their own mount and PID namespaces: every mount (/proc, /sys, /dev, the apt cache) and every process a
# command leaves behind (a roscore, a fake camera) vanishes with it. Needs root, debootstrap, unshare, tar.
#   UWS_CHROOT_CACHE=DIR   base tarballs and downloaded .debs (default /var/cache/underwater_stereo)

uws_chroot_cache=${UWS_CHROOT_CACHE:-/var/cache/underwater_stereo}

# The host's Debian mirror (the first bookworm URI in /etc/apt/sources.list*), so that the chroot's apt uses it.
uws_chroot_mirror() {
  local m
  m=$(sed -n -e 's/^URIs: *\([^ ]*\).*/\1/p' -e 's/^deb \(\[[^]]*\] \)\{0,1\}\([^ ]*\) bookworm .*/\2/p' \
        /etc/apt/sources.list.d/*.sources /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null |
      grep -v security | head -n 1)
  echo "${m:-http://deb.debian.org/debian}"
}

# uws_chroot_create ARCH DIR: a fresh bookworm minbase + git system for ARCH (amd64, arm64) in DIR (created),
# from the cached tarball (made by debootstrap on first use), with the host's apt sources and resolver.
uws_chroot_create() {
  local arch=$1 dir=$2 tarball=$uws_chroot_cache/bookworm-minbase-git-$1.tar
  mkdir -p "$uws_chroot_cache" "$dir"
  if [[ ! -s $tarball ]]; then
    local base mirror
    base=$(mktemp -d "$uws_chroot_cache/debootstrap.XXXXXX")
    mirror=$(uws_chroot_mirror)
    echo "chroot: debootstrap --variant=minbase --include=git bookworm ($arch) from $mirror (cached as $tarball)"
    if ! debootstrap --variant=minbase --arch="$arch" --include=git bookworm "$base" "$mirror" \
         >"$uws_chroot_cache/debootstrap-$arch.log" 2>&1; then
      tail -n 20 "$uws_chroot_cache/debootstrap-$arch.log" >&2
      rm -rf --one-file-system "$base"
      echo "chroot: debootstrap FAILED (log: $uws_chroot_cache/debootstrap-$arch.log)" >&2
      return 1
    fi
    rm -rf "$base"/var/cache/apt/archives/*.deb
    tar -C "$base" -cf "$tarball.tmp" . && mv "$tarball.tmp" "$tarball"
    rm -rf --one-file-system "$base"
  fi
  tar -C "$dir" -xf "$tarball"
  # The host's sources (same mirror, same suites, security included) instead of debootstrap's one line.
  rm -f "$dir/etc/apt/sources.list"
  cp /etc/apt/sources.list.d/*.sources /etc/apt/sources.list.d/*.list "$dir/etc/apt/sources.list.d/" 2>/dev/null || true
  [[ -f /etc/apt/sources.list ]] && cp /etc/apt/sources.list "$dir/etc/apt/"
  cp -L /etc/resolv.conf "$dir/etc/resolv.conf"
  mkdir -p "$uws_chroot_cache/debs-$arch"
}

# uws_chroot_run ARCH DIR [--offline] COMMAND: runs COMMAND (a bash command line) as root in DIR, in new mount and
# PID namespaces (with --offline also a network namespace with only loopback: no network, and ports private, so
# a test's ROS master cannot meet the host's). Downloaded .debs persist in the cache, so that a second run does
# not download them again (apt still installs every package afresh).
uws_chroot_run() {
  local arch=$1 dir=$2 net=()
  shift 2
  if [[ $1 == --offline ]]; then
    net=(--net)
    shift
  fi
  unshare --mount --pid --fork --propagation private "${net[@]}" /bin/sh -euc '
    dir=$1 debs=$2 command=$3
    [ -z "$4" ] || ip link set lo up
    mount --bind "$dir" "$dir"  # / in the chroot a mount point, as on a real machine (unshare needs one)
    mount -t proc proc "$dir/proc"
    mount -t sysfs sysfs "$dir/sys"
    mount --bind /dev "$dir/dev"
    mount -t devpts -o newinstance devpts "$dir/dev/pts"
    mount -t tmpfs tmpfs "$dir/dev/shm"
    mount --bind "$debs" "$dir/var/cache/apt/archives"
    exec chroot "$dir" /usr/bin/env -i HOME=/root TERM=dumb LANG=C.UTF-8 \
      PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin /bin/bash -c "$command"
  ' sh "$dir" "$uws_chroot_cache/debs-$arch" "$*" "${net[*]}"
}

# uws_chroot_remove DIR: kills any process still running in DIR, unmounts anything left under it, removes it.
uws_chroot_remove() {
  local dir=$1 pid m
  [[ -d $dir ]] || return 0
  for pid in /proc/[0-9]*; do
    [[ $(readlink "$pid/root" 2>/dev/null) == "$dir"* ]] && kill -KILL "${pid#/proc/}" 2>/dev/null
  done
  while read -r m; do umount -l "$m" 2>/dev/null || true; done < <(findmnt -rn -o TARGET | grep "^$dir/" | sort -r)
  rm -rf --one-file-system "$dir"
}
