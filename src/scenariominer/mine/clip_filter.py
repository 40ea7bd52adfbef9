"""Coarse-to-fine mining: rank camera crops of objects against the description's keywords with CLIP.

The coarse stage (the paper's section 3.1) keeps only the tracklets whose camera crops look like
what the description names; the program (the fine stage) then runs on those tracks only.

1. :func:`~scenariominer.mine.keywords.extract_keywords` turns the description into short
   phrases ("red car", "bicycle");
2. :class:`ClipEncoder` embeds the phrases with CLIP's text encoder and every object crop with
   its image encoder (a model saved with ``save_pretrained`` in a LOCAL folder; nothing is ever
   downloaded);
3. :func:`rank_crops` scores each crop by its best cosine similarity to a phrase and keeps the
   top K (:class:`~scenariominer.config.mining.ClipFilterConfig`);
4. the kept crops' (track, timestamp) pairs become :class:`CandidateTracklets`; a track is a
   candidate around each kept timestamp (± ``tracklet_margin_s``);
5. :func:`restrict_context` gives the program a log with only the candidate tracks (and the
   ego), and :func:`candidate_cells` the cells its result is limited to.

Camera-frame input (one folder per log; see ``docs/mining.md``): a table ``crops.parquet`` (or
``crops.json``, a list of objects) with one row per object crop and the columns

* ``timestamp_ns`` (int): annotation timestamp of the image;
* ``track_id`` (str): the object's track id in the log;
* ``image`` (str): image file, relative to the folder (several crops may share an image);
* ``x0``, ``y0``, ``x1``, ``y1`` (int): crop box in pixels (left, top, right, bottom; exclusive
  right/bottom), clipped to the image;
* optionally ``camera`` (str) and ``log_id`` (str; rows of other logs are ignored).

torch, transformers and Pillow are imported on first use, with an install hint when missing.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
from numpy.typing import NDArray

from scenariominer import errors as _errors
from scenariominer.config.mining import ClipFilterConfig
from scenariominer.data.log import BoolArray, Log
from scenariominer.llm.errors import MissingDependencyError
from scenariominer.mine.context import LogContext
from scenariominer.mine.keywords import KeywordSet

__all__ = [
    "CROPS_FILES",
    "INSTALL_CLIP_HINT",
    "CameraFrameError",
    "CandidateTracklets",
    "ClipEncoder",
    "ClipModelError",
    "CropEncoder",
    "CropTable",
    "RankedCrops",
    "candidate_cells",
    "candidate_tracklets",
    "rank_crops",
    "restrict_context",
]

INSTALL_CLIP_HINT = "pip install 'scenariominer[embed]' pillow (torch==2.13.0 first)"
#: File names of the crop table in a camera-frame folder, in order of preference.
CROPS_FILES = ("crops.parquet", "crops.json")
_CROP_COLUMNS = ("timestamp_ns", "track_id", "image", "x0", "y0", "x1", "y1")


class CameraFrameError(_errors.MiningError, ValueError):
    """A camera-frame folder or its crop table is missing or malformed; the message names it."""


class ClipModelError(_errors.MiningError, ValueError):
    """The CLIP model folder is missing or does not hold a CLIP model and processor."""


@dataclass(frozen=True, eq=False)
class CropTable:
    """Object crops of one log's camera images.

    Attributes:
        root: folder the image paths are relative to.
        timestamps_ns: ``(M,)`` int64 timestamp of each crop.
        track_ids: ``(M,)`` str track of each crop.
        images: ``(M,)`` str image file of each crop (relative to ``root``).
        boxes: ``(M, 4)`` int64 ``x0, y0, x1, y1`` pixel boxes.
    """

    root: Path
    timestamps_ns: NDArray[np.int64]
    track_ids: NDArray[np.str_]
    images: NDArray[np.str_]
    boxes: NDArray[np.int64]

    def __len__(self) -> int:
        return int(self.timestamps_ns.shape[0])

    @classmethod
    def read(cls, folder: str | Path, log_id: str | None = None) -> CropTable:
        """Read the crop table of a camera-frame folder (see the module docstring).

        Args:
            folder: the folder holding ``crops.parquet`` or ``crops.json`` and the images.
            log_id: keep only rows of this log when the table has a ``log_id`` column.

        Raises:
            CameraFrameError: no crop table, missing columns, bad values or empty boxes.
        """
        root = Path(folder)
        path = next((root / n for n in CROPS_FILES if (root / n).is_file()), None)
        if path is None:
            raise CameraFrameError(f"{root}: no {' or '.join(CROPS_FILES)} (the camera-frame crop table)")
        try:
            if path.suffix == ".parquet":
                table = pq.read_table(path)
            else:
                rows = json.loads(path.read_text(encoding="utf-8"))
                if not isinstance(rows, list):
                    raise CameraFrameError(f"{path}: expected a JSON list of crop objects")
                table = pa.Table.from_pylist(rows) if rows else pa.table({c: [] for c in _CROP_COLUMNS})
        except (OSError, ValueError, pa.ArrowInvalid) as exc:
            if isinstance(exc, CameraFrameError):
                raise
            raise CameraFrameError(f"{path}: cannot read the crop table ({exc})") from None
        missing = [c for c in _CROP_COLUMNS if c not in table.column_names]
        if missing:
            raise CameraFrameError(f"{path}: missing column(s) {missing}; need {list(_CROP_COLUMNS)}")
        if log_id is not None and "log_id" in table.column_names:
            keep = np.asarray(table.column("log_id").to_numpy(zero_copy_only=False)).astype(str) == log_id
            table = table.filter(pa.array(keep))
        try:
            ts = np.asarray(table.column("timestamp_ns").to_numpy(zero_copy_only=False), dtype=np.int64)
            boxes = np.stack(
                [
                    np.asarray(table.column(c).to_numpy(zero_copy_only=False), dtype=np.int64)
                    for c in _CROP_COLUMNS[3:]
                ],
                axis=1,
            ).reshape(-1, 4)
        except (TypeError, ValueError) as exc:
            raise CameraFrameError(f"{path}: timestamps and boxes must be integers ({exc})") from None
        empty = (boxes[:, 2] <= boxes[:, 0]) | (boxes[:, 3] <= boxes[:, 1])
        if empty.any():
            raise CameraFrameError(f"{path}: row {int(np.flatnonzero(empty)[0])} has an empty crop box")
        return cls(
            root=root,
            timestamps_ns=ts,
            track_ids=np.asarray(table.column("track_id").to_numpy(zero_copy_only=False)).astype(str),
            images=np.asarray(table.column("image").to_numpy(zero_copy_only=False)).astype(str),
            boxes=boxes,
        )


@runtime_checkable
class CropEncoder(Protocol):
    """Embeds texts and image crops into one space (unit vectors; cosine = dot product)."""

    def encode_text(self, texts: Sequence[str]) -> NDArray[np.float32]:
        """``(len(texts), D)`` unit text embeddings."""
        ...

    def encode_images(self, images: Sequence[Any]) -> NDArray[np.float32]:
        """``(len(images), D)`` unit embeddings of PIL images."""
        ...


class ClipEncoder:
    """CLIP text and image embeddings (L2-normalised float32), from a local model folder.

    Args:
        model: a ``transformers.CLIPModel``.
        processor: the matching ``transformers.CLIPProcessor``.
        batch_size: images per forward pass.
        device: torch device.
    """

    def __init__(self, model: Any, processor: Any, *, batch_size: int = 32, device: str = "cpu") -> None:
        self.model = model
        self.processor = processor
        self.batch_size = batch_size
        self.device = device

    @classmethod
    def from_pretrained(cls, path: str | Path, *, batch_size: int = 32, device: str = "cpu") -> ClipEncoder:
        """Load a CLIP model and processor saved with ``save_pretrained`` in ``path`` (never downloads).

        Raises:
            ClipModelError: ``path`` is empty, missing, or not a CLIP model folder.
            MissingDependencyError: torch or transformers is not installed.
        """
        if not str(path):
            raise ClipModelError("no CLIP model folder given (set mining.clip.model_path)")
        folder = Path(path).expanduser()
        if not folder.is_dir():
            raise ClipModelError(
                f"CLIP model folder {str(folder)!r} does not exist; give the folder of a model saved "
                "with save_pretrained (e.g. openai/clip-vit-base-patch32, downloaded beforehand); "
                "nothing is downloaded"
            )
        if not (folder / "config.json").is_file():
            raise ClipModelError(f"{folder} has no config.json: not a model saved with save_pretrained")
        try:
            import torch  # noqa: F401
            from transformers import CLIPModel, CLIPProcessor
        except ImportError as exc:
            raise MissingDependencyError(
                str(exc.name or "transformers"), "the CLIP crop filter", INSTALL_CLIP_HINT
            ) from None
        try:
            model: Any = CLIPModel.from_pretrained(str(folder), local_files_only=True)
            processor: Any = CLIPProcessor.from_pretrained(str(folder), local_files_only=True)
        except (OSError, ValueError, KeyError) as exc:
            raise ClipModelError(f"{folder}: cannot load a CLIP model and processor ({exc})") from None
        model.eval()
        model.to(device)
        return cls(model, processor, batch_size=batch_size, device=device)

    @staticmethod
    def _features(out: Any) -> Any:
        """Projected embeddings from ``get_*_features`` (a tensor, or an output with ``pooler_output``)."""
        return out if hasattr(out, "norm") else out.pooler_output

    @staticmethod
    def _unit(x: Any) -> NDArray[np.float32]:
        arr = np.asarray(x.detach().cpu().numpy(), dtype=np.float32)
        norms = np.linalg.norm(arr, axis=1, keepdims=True)
        out: NDArray[np.float32] = np.divide(arr, norms, out=np.zeros_like(arr), where=norms > 0)
        return out

    def encode_text(self, texts: Sequence[str]) -> NDArray[np.float32]:
        """``(len(texts), D)`` unit text embeddings."""
        import torch

        inputs = self.processor(text=list(texts), return_tensors="pt", padding=True, truncation=True)
        inputs = {k: v.to(self.device) for k, v in inputs.items() if k in ("input_ids", "attention_mask")}
        with torch.inference_mode():
            out = self.model.get_text_features(**inputs)
        return self._unit(self._features(out))

    def encode_images(self, images: Sequence[Any]) -> NDArray[np.float32]:
        """``(len(images), D)`` unit image embeddings of PIL images, in batches."""
        import torch

        parts: list[NDArray[np.float32]] = []
        for start in range(0, len(images), self.batch_size):
            batch = list(images[start : start + self.batch_size])
            inputs = self.processor(images=batch, return_tensors="pt")
            with torch.inference_mode():
                out = self.model.get_image_features(pixel_values=inputs["pixel_values"].to(self.device))
            parts.append(self._unit(self._features(out)))
        if not parts:
            dim = int(self.model.config.projection_dim)
            return np.zeros((0, dim), dtype=np.float32)
        return np.concatenate(parts, axis=0)


def _load_crops(crops: CropTable, indices: NDArray[np.int64]) -> list[Any]:
    """The PIL crops of the given rows (each image file is opened once)."""
    try:
        from PIL import Image
    except ImportError:
        raise MissingDependencyError("PIL", "the CLIP crop filter", INSTALL_CLIP_HINT) from None
    opened: dict[str, Any] = {}
    out = []
    for i in indices:
        name = str(crops.images[i])
        if name not in opened:
            path = crops.root / name
            try:
                with Image.open(path) as img:
                    opened[name] = img.convert("RGB")
            except (OSError, ValueError) as exc:
                raise CameraFrameError(f"{path}: cannot open the image ({exc})") from None
        img = opened[name]
        x0, y0, x1, y1 = (int(v) for v in crops.boxes[i])
        x0, y0 = max(0, x0), max(0, y0)
        x1, y1 = min(img.width, x1), min(img.height, y1)
        if x1 <= x0 or y1 <= y0:
            raise CameraFrameError(
                f"{crops.root / name}: crop {crops.boxes[i].tolist()} lies outside the image"
            )
        out.append(img.crop((x0, y0, x1, y1)))
    return out


@dataclass(frozen=True, eq=False)
class RankedCrops:
    """Crops ranked by similarity to the keywords.

    Attributes:
        phrases: the texts that were embedded.
        scores: ``(M,)`` float32 best cosine similarity of every crop to a phrase.
        kept: ``(K,)`` int64 indices of the kept crops, best first.
    """

    phrases: tuple[str, ...]
    scores: NDArray[np.float32]
    kept: NDArray[np.int64]


def rank_crops(
    keywords: KeywordSet, crops: CropTable, encoder: CropEncoder, config: ClipFilterConfig | None = None
) -> RankedCrops:
    """Score every crop against the keyword phrases and keep the top K.

    A crop's score is its highest cosine similarity to any phrase (put through
    ``config.text_template``); the ``top_k_crops`` best crops at or above ``min_similarity``
    are kept (ties keep the earlier row).
    """
    cfg = config or ClipFilterConfig()
    phrases = tuple(keywords.phrases(include_spatial=cfg.use_spatial_keywords))
    if len(crops) == 0:
        return RankedCrops(phrases, np.zeros(0, dtype=np.float32), np.zeros(0, dtype=np.int64))
    text = encoder.encode_text([cfg.text_template.format(p) for p in phrases])
    scores = np.empty(len(crops), dtype=np.float32)
    step = max(1, cfg.batch_size)
    for start in range(0, len(crops), step):
        idx = np.arange(start, min(start + step, len(crops)), dtype=np.int64)
        emb = encoder.encode_images(_load_crops(crops, idx))
        scores[idx] = (emb @ text.T).max(axis=1)
    order = np.argsort(-scores, kind="stable")
    order = order[scores[order] >= cfg.min_similarity][: cfg.top_k_crops]
    return RankedCrops(phrases, scores, order.astype(np.int64))


@dataclass(frozen=True)
class CandidateTracklets:
    """Tracks (and times) the coarse stage lets through for one log.

    Attributes:
        log_id: the log.
        timestamps_by_track: ``{track_id: (k,) int64 timestamps of its kept crops}``.
        margin_s: a track is a candidate within this many seconds of each kept timestamp.
    """

    log_id: str
    timestamps_by_track: dict[str, NDArray[np.int64]]
    margin_s: float = 1.0

    @property
    def track_ids(self) -> list[str]:
        """Candidate track ids, sorted."""
        return sorted(self.timestamps_by_track)


def candidate_tracklets(
    log_id: str, crops: CropTable, ranked: RankedCrops, margin_s: float = 1.0
) -> CandidateTracklets:
    """Group the kept crops by track into candidate tracklets."""
    by_track: dict[str, list[int]] = {}
    for i in ranked.kept:
        by_track.setdefault(str(crops.track_ids[i]), []).append(int(crops.timestamps_ns[i]))
    return CandidateTracklets(
        log_id, {k: np.unique(np.asarray(v, dtype=np.int64)) for k, v in by_track.items()}, margin_s
    )


def candidate_cells(log: Log, tracklets: CandidateTracklets) -> BoolArray:
    """``(N, T)`` cells of ``log`` inside a candidate tracklet (observed cells only).

    Raises:
        ValueError: the tracklets belong to another log.
    """
    if tracklets.log_id != log.log_id:
        raise ValueError(f"tracklets of log {tracklets.log_id} applied to log {log.log_id}")
    mask = np.zeros((log.n_tracks, log.n_timestamps), dtype=bool)
    margin_ns = int(round(tracklets.margin_s * 1e9))
    index = {str(t): i for i, t in enumerate(log.track_ids)}
    for track_id, stamps in tracklets.timestamps_by_track.items():
        row = index.get(track_id)
        if row is None or stamps.size == 0:
            continue
        ts = log.timestamps_ns
        pos = np.searchsorted(stamps, ts)
        before = np.abs(ts - stamps[np.clip(pos - 1, 0, stamps.size - 1)])
        after = np.abs(stamps[np.clip(pos, 0, stamps.size - 1)] - ts)
        mask[row] = np.minimum(before, after) <= margin_ns
    return mask & log.valid


def restrict_context(context: LogContext, cells: BoolArray) -> tuple[LogContext, BoolArray]:
    """A context over the ego plus the tracks with candidate cells, and those cells on it.

    Args:
        context: the full log.
        cells: ``(N, T)`` candidate cells of ``context``'s log.

    Returns:
        ``(reduced context, (N', T) candidate cells of the reduced log)``; the reduced log keeps
        the ego at row 0, the map, the timestamps and the track ids.
    """
    log = context.log
    keep: BoolArray = np.asarray(np.asarray(cells, dtype=bool).any(axis=1))
    keep[log.ego_index] = True
    rows = np.flatnonzero(keep).astype(np.int64)
    reduced = log.select_tracks(rows)
    hd_map = None
    if log.map_dir is None and context.has_map:
        hd_map = context.require_map("restrict_context")
    return LogContext(reduced, context.config, hd_map), np.asarray(cells, dtype=bool)[rows]
