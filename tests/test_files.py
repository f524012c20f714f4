"""One cache key, the SHA-256 of the package's sources (no hand-kept lists of
"the modules a result depends on"; model/kinematics.py was in none of them)."""

import hashlib
import os
import shutil
from pathlib import Path

import gd_analyze
from gd_analyze.files import current_umask, package_sha256, sources_sha256

PACKAGE = Path(gd_analyze.__file__).resolve().parent


def _oracle(root):
    """hashlib over each .py file's relative path, size and bytes, in path order."""
    digest = hashlib.sha256()
    files = sorted((p.relative_to(root).as_posix(), p) for p in root.rglob("*.py"))
    for rel, p in files:
        data = p.read_bytes()
        digest.update(f"{rel}\0{len(data)}\0".encode() + data)
    return digest.hexdigest()


def test_package_sha256_covers_every_source(tmp_path):
    copy = tmp_path / "gd_analyze"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    assert package_sha256() == sources_sha256(copy) == _oracle(PACKAGE)
    seen = {package_sha256()}
    # an edit of a module no list named, a new module, a renamed one: each a new key
    kin = copy / "model" / "kinematics.py"
    kin.write_bytes(kin.read_bytes() + b"\n")
    seen.add(sources_sha256(copy))
    (copy / "store" / "new_module.py").write_text("X = 1\n")
    seen.add(sources_sha256(copy))
    (copy / "store" / "new_module.py").rename(copy / "store" / "new_modul.py")
    seen.add(sources_sha256(copy))
    assert len(seen) == 4
    # data files are not code
    (copy / "store" / "notes.txt").write_text("x")
    assert sources_sha256(copy) in seen


def test_every_cache_key_carries_the_package_sha256(puma):
    from gd_analyze.certify.region import joint_region
    from gd_analyze.store.certification_cache import certification_key, search_key
    from gd_analyze.store.explicit_cache import cache_key

    region = joint_region(puma, puma.qdd_max)
    code = package_sha256()
    assert cache_key(puma)["code"]["sha256"] == code
    assert certification_key(puma, region, {})["code"]["sha256"] == code
    assert search_key(puma, region, 0.01, 0.0, 8)["code"]["sha256"] == code


def test_current_umask_reads_the_mask_and_leaves_it():
    old = os.umask(0o027)
    try:
        assert current_umask() == 0o027
        assert current_umask() == 0o027         # reading it did not change it
    finally:
        os.umask(old)
