#!/usr/bin/env bash
# Fetch a few CAD meshes from Debian's libcgal-demo package into DEST (default tests/data/cgal).
#
#   tests/fetch_cgal_meshes.sh [DEST]
#
# Downloads the pinned .deb with `apt-get download` (no installation, the system is not
# touched), checks its sha256, unpacks it in a temporary directory and copies the meshes
# listed in cgal_meshes.sha256 (next to this script) into DEST, checking each file's sha256.
# A second run whose files are all present and intact does nothing.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
pins="$here/cgal_meshes.sha256"
dest="${1:-$here/data/cgal}"
package=libcgal-demo
version=5.5.1-2
deb="${package}_${version}_all.deb"
member_dir=usr/share/doc/libcgal-dev
data_tar="$member_dir/data.tar.gz"

die() { echo "fetch_cgal_meshes: $*" >&2; exit 1; }

[[ -f "$pins" ]] || die "the checksum list $pins is missing; restore it from git."
pinned() { awk -v f="$1" '$1 !~ /^#/ && $2 == f { print $1 }' "$pins"; }
meshes=($(awk '$1 !~ /^#/ && $2 ~ /\.off$/ { print $2 }' "$pins"))
deb_sum="$(pinned "$deb")"
[[ -n "$deb_sum" && ${#meshes[@]} -gt 0 ]] || die "$pins has no pin for $deb or no mesh; restore it from git."

# Fast path: everything already there and intact.
all_ok=1
for m in "${meshes[@]}"; do
    if [[ ! -f "$dest/$m" ]]; then
        echo "fetch_cgal_meshes: $dest/$m is missing; fetching."
        all_ok=0
        break
    elif [[ "$(sha256sum "$dest/$m" | cut -d' ' -f1)" != "$(pinned "$m")" ]]; then
        echo "fetch_cgal_meshes: $dest/$m differs from its pinned sha256 (altered?); fetching a fresh copy."
        all_ok=0
        break
    fi
done
if [[ $all_ok == 1 ]]; then
    echo "fetch_cgal_meshes: ${#meshes[@]} meshes already in $dest, checksums match."
    exit 0
fi

command -v apt-get >/dev/null && command -v dpkg-deb >/dev/null \
    || die "apt-get and dpkg-deb are needed (a Debian or Ubuntu system)."

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

echo "fetch_cgal_meshes: downloading $package=$version ..."
if ! (cd "$tmp" && apt-get download -q "$package=$version" >"$tmp/apt.log" 2>&1); then
    cat "$tmp/apt.log" >&2
    die "could not download $package version $version. Run 'apt-get update' (as root) and retry.
If 'apt-cache policy $package' no longer offers $version, check the new package's data files
and copyright, then update the pins in $pins, the version in this script and meshes/catalog.md."
fi
[[ -f "$tmp/$deb" ]] || die "apt-get did not produce $deb (got: $(ls "$tmp"))."

got="$(sha256sum "$tmp/$deb" | cut -d' ' -f1)"
[[ "$got" == "$deb_sum" ]] || die "$deb has sha256 $got, but $pins pins $deb_sum.
The download was altered or the archive republished the package. Do not use it; retry
later, and if it persists compare the package by hand before changing the pin."

dpkg-deb -x "$tmp/$deb" "$tmp/root"
[[ -f "$tmp/root/$data_tar" ]] || die "$deb holds no $data_tar; the package layout changed."
members=()
for m in "${meshes[@]}"; do members+=("data/meshes/$m"); done
tar -xzf "$tmp/root/$data_tar" -C "$tmp" "${members[@]}" \
    || die "$data_tar lacks one of: ${meshes[*]}."

mkdir -p "$dest"
for m in "${meshes[@]}"; do
    got="$(sha256sum "$tmp/data/meshes/$m" | cut -d' ' -f1)"
    [[ "$got" == "$(pinned "$m")" ]] || die "$m from $deb has sha256 $got, expected $(pinned "$m").
The pinned package verified, so the pin list itself is wrong: restore $pins from git."
    cp "$tmp/data/meshes/$m" "$dest/$m.part" && mv -f "$dest/$m.part" "$dest/$m"
done
echo "fetch_cgal_meshes: ${#meshes[@]} meshes from $package $version verified and copied into $dest."
