#!/usr/bin/env python3
"""Record the ground truth of the CAD mirror benchmark's catalog set: download a furniture
catalog package, pick its chairs, tables, lamps and vehicles by name, run the brute-force
oracle (tests/oracle_mirror.py, never the detector) on each, and write tests/cad_catalog.json
and the pins tests/cad_catalog.sha256.

    python tests/record_cad_catalog.py [--only MEMBER ...] [--jobs N]

The package is Debian's `sweethome3d-furniture` (its archive pinned in cad_catalog.sha256):
five catalogs of OBJ models, each a zip archive (.sh3f) with a catalog of names.  A model is
kept when its English name matches CATEGORY and the oracle's verdict is clear (its mirror
planes stand out from every other plane by oracle_mirror.CLEAR_MARGIN).  Every plane the
oracle accepts is written with its residuals; the benchmark decides which count as global.
The run is deterministic; one to two minutes per model and process (--jobs runs several at
once).  With --only, the other models' entries are kept as they are.
"""
import argparse
import hashlib
import json
import multiprocessing
import os
import re
import subprocess
import sys
import tempfile
import zipfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import oracle_mirror  # noqa: E402
import real_models  # noqa: E402
from record_real_models import ORACLE, plane_entry  # noqa: E402

PACKAGE, VERSION = "sweethome3d-furniture", "1.8-1"
REGISTRY = "Debian 12 bookworm main, all (apt-get download)"
FOLDER = "usr/share/sweethome3d/furniture"
LICENSES = {
    "BlendSwap-CC-0": "CC0 (debian/copyright of sweethome3d-furniture 1.8-1, Files: BlendSwap-CC-0/*)",
    "BlendSwap-CC-BY": "CC-BY-3.0 (debian/copyright, Files: BlendSwap-CC-BY/*: the BlendSwap contributors)",
    "KatorLegaz": "CC-BY-3.0-US (debian/copyright: Andrew Kator & Jennifer Legaz)",
    "Scopia": "CC-BY-3.0 (debian/copyright: Scopia Visual Interfaces Systems)",
}
#: the objects of the issue's collection: chairs, tables, lamps, vehicles, vessels, aircraft
CATEGORY = re.compile(r"chair|table|lamp|bench|stool|desk|sedan|beetle|\bcar\b|car model|leon|peugeot|"
                      r"renault|focus|suv|\bvan\b|smart|truck|boat|plane|\bbus\b|motor|bike|chevrolet|scooter",
                      re.IGNORECASE)


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def pinned_archive():
    for line in open(real_models.CAD_CATALOG_PINS):
        parts = line.split()
        if len(parts) == 2 and not line.startswith("#") and parts[1].endswith(".deb"):
            return parts
    raise SystemExit(f"{real_models.CAD_CATALOG_PINS} pins no .deb")


def download(workdir):
    """The package's catalogs unpacked into workdir/CATALOG/, after checking its pin."""
    want, name = pinned_archive()
    subprocess.run(["apt-get", "download", "-q", f"{PACKAGE}={VERSION}"], cwd=workdir, check=True)
    deb = os.path.join(workdir, name)
    if sha256(deb) != want:
        raise SystemExit(f"{name} does not match its pin")
    subprocess.run(["dpkg-deb", "-x", deb, os.path.join(workdir, "root")], check=True)
    catalogs = {}
    for archive in sorted(os.listdir(os.path.join(workdir, "root", FOLDER))):
        catalog = archive[:-len(".sh3f")]
        with zipfile.ZipFile(os.path.join(workdir, "root", FOLDER, archive)) as z:
            z.extractall(os.path.join(workdir, catalog))
        catalogs[catalog] = os.path.join(workdir, catalog)
    return catalogs


def candidates(catalog_dir):
    """(name, model path inside the catalog) of the catalog's models of the categories."""
    props = os.path.join(catalog_dir, "PluginFurnitureCatalog.properties")
    names, models = {}, {}
    for line in open(props, encoding="latin-1"):
        m = re.match(r"(name|model)#(\d+)=(.*)", line.strip())
        if m:
            (names if m.group(1) == "name" else models)[m.group(2)] = m.group(3)
    return [(names[k], models[k].lstrip("/")) for k in sorted(models, key=int)
            if k in names and CATEGORY.search(names[k]) and models[k].endswith(".obj")]


def entry(job):
    catalog, name, member, path = job
    V, F = oracle_mirror.load_mesh(path)
    res = oracle_mirror.find_mirror_planes(V, F, **ORACLE)
    if not res.is_clear:
        return None
    return dict(name=f"{catalog}/{os.path.basename(member)[:-4]}", file=f"{PACKAGE}/{catalog}/{member}",
                package=PACKAGE, version=VERSION, registry=REGISTRY, license=LICENSES[catalog],
                triangles=int(len(F)), diagonal=round(res.diag, 9),
                centroid=[round(float(x), 9) for x in res.centroid], kind="exact",
                planes=[plane_entry(p, res.centroid) for p in res.planes],
                best_other_plane=res.rejected[0].as_dict(), notes=name)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", nargs="+", metavar="MEMBER", help="only these members (CATALOG/PATH)")
    ap.add_argument("--jobs", type=int, default=1, help="models measured at once")
    args = ap.parse_args(argv)
    old = {}
    if args.only and os.path.exists(real_models.CAD_CATALOG):
        old = {m["file"]: m for m in json.load(open(real_models.CAD_CATALOG))["models"]}
    with tempfile.TemporaryDirectory() as work:
        catalogs = download(work)
        models, pins, jobs = [], [], []
        for catalog, d in catalogs.items():
            for name, member in candidates(d):
                key = f"{PACKAGE}/{catalog}/{member}"
                path = os.path.join(d, member)
                pins.append((sha256(path), key))
                if args.only and f"{catalog}/{member}" not in args.only:
                    if key in old:
                        models.append(old[key])
                    continue
                jobs.append((catalog, name, member, path))
        with multiprocessing.Pool(args.jobs) as pool:
            for (catalog, _, member, _), e in zip(jobs, pool.imap(entry, jobs)):
                print(f"{catalog}/{member}: {'clear, %d plane(s)' % len(e['planes']) if e else 'not clear, left out'}",
                      flush=True)
                if e:
                    models.append(e)
    kept = {m["file"] for m in models}
    doc = dict(about="Global mirror planes of the chairs, tables, lamps and vehicles of a furniture catalog package, "
                     "measured by tests/oracle_mirror.py (python tests/record_cad_catalog.py). A plane is unit normal n "
                     "and offset d: n . x = d in the file's own coordinates. Residuals are fractions of the bounding-box "
                     "diagonal (within_*: fractions of the area).",
               oracle=ORACLE, models=sorted(models, key=lambda m: m["file"]))
    with open(real_models.CAD_CATALOG, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    archive = pinned_archive()
    with open(real_models.CAD_CATALOG_PINS, "w") as f:
        f.write(f"# Pins for tests/fetch_real_models.sh DEST tests/cad_catalog.sha256 (sha256sum format),\n"
                f"# written by tests/record_cad_catalog.py. {PACKAGE} {VERSION} (Debian 12 \"bookworm\", main,\n"
                f"# all); members CATALOG/PATH of the zip archive {FOLDER}/CATALOG.sh3f\n")
        f.write(f"{archive[0]}  {archive[1]}\n")
        for digest, key in sorted(pins, key=lambda p: p[1]):
            if key in kept:
                f.write(f"{digest}  {key}\n")
    print(f"{len(models)} models written to {real_models.CAD_CATALOG}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
