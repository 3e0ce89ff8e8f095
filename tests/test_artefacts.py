"""Artefact integrity: manifest hashes, clear errors on missing / stale / corrupted files."""
from __future__ import annotations

import json
import shutil

import pytest

from curvedvoronoi.runtime.artefacts import ArtefactError, generated_dir, load_manifest, load_offset, verified_bytes
from curvedvoronoi.precompute.artefacts import sha256_file


@pytest.fixture()
def copy_of_generated(tmp_path):
    dst = tmp_path / "generated"
    shutil.copytree(generated_dir(), dst, ignore=shutil.ignore_patterns("__pycache__"))
    return dst


def test_manifest_lists_every_artefact_with_its_hash():
    root = generated_dir()
    manifest = load_manifest()
    files = {p.relative_to(root).as_posix() for p in root.rglob("*")
             if p.is_file() and p.name not in ("MANIFEST.json", "__init__.py") and "__pycache__" not in p.parts}
    assert files == set(manifest["artefacts"])
    for rel, entry in manifest["artefacts"].items():
        assert sha256_file(root / rel) == entry["sha256"]
        assert entry["inputs"], rel


def test_one_flipped_byte_is_detected(copy_of_generated):
    target = copy_of_generated / "offsets" / "ellipse.json"
    data = bytearray(target.read_bytes())
    i = data.index(b'"1"')           # a coefficient
    data[i + 1] = ord("3")
    target.write_bytes(bytes(data))
    with pytest.raises(ArtefactError, match="corrupted"):
        load_offset("ellipse", root=copy_of_generated)
    load_offset("parabola", root=copy_of_generated)   # the others still load


def test_missing_artefact_and_manifest(copy_of_generated):
    (copy_of_generated / "offsets" / "parabola.json").unlink()
    with pytest.raises(ArtefactError, match="missing artefact"):
        load_offset("parabola", root=copy_of_generated)
    with pytest.raises(ArtefactError, match="not listed"):
        verified_bytes("offsets/nonexistent.json", root=copy_of_generated)
    (copy_of_generated / "MANIFEST.json").unlink()
    with pytest.raises(ArtefactError, match="missing artefact manifest"):
        load_offset("circle", root=copy_of_generated)


def test_stale_generator_version_is_refused(copy_of_generated):
    path = copy_of_generated / "MANIFEST.json"
    doc = json.loads(path.read_text())
    doc["generator_version"] = "0"
    path.write_text(json.dumps(doc))
    with pytest.raises(ArtefactError, match="stale"):
        load_offset("ellipse", root=copy_of_generated)


def test_garbage_manifest(copy_of_generated):
    (copy_of_generated / "MANIFEST.json").write_text("{not json")
    with pytest.raises(ArtefactError, match="not valid JSON"):
        load_offset("ellipse", root=copy_of_generated)


def test_interval_route_takes_offsets_only_from_verified_artefacts(copy_of_generated, monkeypatch):
    """The ch. 6 route has no second derivation of the offsets: a corrupted artefact stops it with
    ArtefactError instead of being bypassed (and the intact artefacts give the App. B.4 offset)."""
    from curvedvoronoi.runtime.interval import offsets as ioff

    assert len(ioff.canonical_offset("ellipse_hyperbola").terms) == len(load_offset("ellipse").terms) == 104
    target = copy_of_generated / "offsets" / "parabola.json"
    data = bytearray(target.read_bytes())
    i = data.index(b'"1"')
    data[i + 1] = ord("3")
    target.write_bytes(bytes(data))
    monkeypatch.setenv("CURVEDVORONOI_GENERATED", str(copy_of_generated))
    ioff.canonical_offset.cache_clear()
    try:
        with pytest.raises(ArtefactError, match="corrupted"):
            ioff.canonical_offset("parabola")
    finally:
        ioff.canonical_offset.cache_clear()
