#!/usr/bin/env bash
# Fetch and verify a MeshLab upstream source (it bundles vcglib) from Debian's source
# package, without touching the system's apt sources: a private sources list and state
# directory live under DEST_DIR.
#   2025.07 (the default): the "sid" suite; pymeshlab's and the GUI's plugin API.
#   2020.09: the "bookworm" suite; the plugin API of Debian 12's meshlabserver.
#
# usage: fetch_meshlab_source.sh DEST_DIR [2025.07|2020.09]
# Leaves DEST_DIR/meshlab (2025.07) or DEST_DIR/meshlab-2020.09 (the unpacked tree) and
# exits 0, or explains what failed.
set -euo pipefail

DEST=${1:?usage: fetch_meshlab_source.sh DEST_DIR [2025.07|2020.09]}
RELEASE=${2:-2025.07}
case "$RELEASE" in
  2025.07)
    TARBALL=meshlab_2025.07~dfsg.orig.tar.xz
    SHA256=d22c98d362f2a284e481af8dbfc272b2222f5b9c67b3cf8bec57d1c3161886f4
    PKGVER=2025.07~dfsg-4
    SUITE=sid
    TOPDIR=meshlab-dc48b91ae562756a6988048c5d5c7f1d2b687256
    UNPACKED=meshlab ;;
  2020.09)
    TARBALL=meshlab_2020.09+dfsg1.orig.tar.xz
    SHA256=d6715352ff65caffdec0292858d4263eb0c3cbbf3b1e5c2e2bab218e3f234630
    PKGVER=2020.09+dfsg1-2
    SUITE=bookworm
    TOPDIR=meshlab-a595226b8b02505afbf9fd4ffbccbd6011046ae6
    UNPACKED=meshlab-2020.09 ;;
  *) echo "error: unknown MeshLab release '$RELEASE' (2025.07 or 2020.09)." >&2; exit 1 ;;
esac

mkdir -p "$DEST"
cd "$DEST"
if [ -f "$UNPACKED/.verified" ]; then exit 0; fi

verify() { echo "$SHA256  $TARBALL" | sha256sum --check --status; }

if [ ! -f "$TARBALL" ] || ! verify; then
  rm -f "$TARBALL"
  # The Debian mirror this machine already uses, read from its own apt configuration,
  # so that no host name is written into the repository.
  mirror=$( (grep -h '^URIs:' /etc/apt/sources.list.d/*.sources 2>/dev/null;
             grep -h '^deb ' /etc/apt/sources.list 2>/dev/null | awk '{print "URIs: "$2}'; true) \
           | awk '{print $2}' | grep -v -- '-security' | grep '/debian/\?$' | head -n 1 || true)
  if [ -z "$mirror" ]; then
    echo "error: no Debian mirror found in /etc/apt; cannot fetch the MeshLab source package." >&2
    echo "       Put $TARBALL (sha256 $SHA256) into $DEST by hand and run make again." >&2
    exit 1
  fi
  apt_dir=$PWD/apt-$SUITE
  mkdir -p "$apt_dir/lists/partial" "$apt_dir/archives/partial"
  echo "deb-src [trusted=yes] $mirror $SUITE main" > "$apt_dir/sources.list"
  apt_opts=(-o Dir::Etc::SourceList="$apt_dir/sources.list" -o Dir::Etc::SourceParts=/dev/null
            -o Dir::State::Lists="$apt_dir/lists" -o Dir::Cache::Archives="$apt_dir/archives"
            -o APT::Sandbox::User=root -o Debug::NoLocking=1)
  apt-get -qq "${apt_opts[@]}" update
  # The .dsc of a superseded Debian revision can vanish while the upstream tarball stays;
  # only the tarball matters, and it is checked against the pinned checksum below.
  apt-get -qq "${apt_opts[@]}" source --download-only "meshlab=$PKGVER" > apt-source-$SUITE.log 2>&1 || true
  if [ ! -f "$TARBALL" ]; then
    cat apt-source-$SUITE.log >&2
    echo "error: Debian's source package meshlab=$PKGVER did not provide $TARBALL." >&2
    echo "       The $SUITE suite may have moved on; put the tarball (sha256 $SHA256) into $DEST by hand." >&2
    exit 1
  fi
fi
if ! verify; then
  echo "error: $DEST/$TARBALL does not have the pinned sha256 $SHA256." >&2
  echo "       It was altered or is a different release; delete it and run make again." >&2
  exit 1
fi
rm -rf "$UNPACKED" "$TOPDIR"
tar xf "$TARBALL"
mv "$TOPDIR" "$UNPACKED"
touch "$UNPACKED/.verified"
