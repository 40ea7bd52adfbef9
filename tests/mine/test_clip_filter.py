"""Coarse-to-fine CLIP filter: crop tables, ranking, candidate tracklets, restricted mining."""

from __future__ import annotations

import json
import string
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from mining_scenes import T_S, Obj, const, make_log

from scenariominer.config.mining import ClipFilterConfig, MiningConfig
from scenariominer.data.log import Log
from scenariominer.mine.clip_filter import (
    CameraFrameError,
    CandidateTracklets,
    ClipEncoder,
    ClipModelError,
    CropEncoder,
    CropTable,
    candidate_cells,
    candidate_tracklets,
    rank_crops,
    restrict_context,
)
from scenariominer.mine.context import LogContext
from scenariominer.mine.keywords import KeywordSet, ObjectPhrase
from scenariominer.mine.query import clip_candidates, mine_logs
from scenariominer.mine.sandbox import ProgramResult, run_trusted_program

Image = pytest.importorskip("PIL.Image")

COLOURS = {"red": (255, 0, 0), "green": (0, 160, 0), "blue": (0, 0, 255)}


class MeanColourEncoder:
    """A fake CLIP: a text embeds to the RGB direction of its colour word, an image to its mean colour."""

    def encode_text(self, texts: Sequence[str]) -> np.ndarray:
        out = []
        for text in texts:
            rgb = next((c for name, c in COLOURS.items() if name in text), (1, 1, 1))
            out.append(np.asarray(rgb, dtype=np.float32))
        v = np.stack(out)
        return v / np.linalg.norm(v, axis=1, keepdims=True)

    def encode_images(self, images: Sequence[Any]) -> np.ndarray:
        v = np.stack([np.asarray(img, dtype=np.float32).reshape(-1, 3).mean(axis=0) for img in images])
        return v / np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-9)


def scene_log() -> Log:
    """The ego, a red car, a blue car and a green bicycle over 6 s at 10 Hz (positions do not matter)."""
    zero = const(0.0)
    return make_log(
        [
            Obj("ego", "EGO_VEHICLE", 10 * T_S, zero, zero),
            Obj("red_car", "REGULAR_VEHICLE", 20 + 10 * T_S, const(3.5), zero),
            Obj("blue_car", "REGULAR_VEHICLE", 40 + 10 * T_S, const(-3.5), zero),
            Obj("bike", "BICYCLE", 10 * T_S, const(-3.0), zero, 1.8, 0.6),
        ],
        log_id="cams",
    )


def write_frames(folder: Path, log: Log, fmt: str = "parquet") -> Path:
    """One 120x40 image per second: red (x 0-40), blue (40-80), green (80-120) blocks, one crop each."""
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    for k, col in enumerate(range(0, log.n_timestamps, 10)):
        img = Image.new("RGB", (120, 40), (128, 128, 128))
        for j, colour in enumerate(("red", "blue", "green")):
            img.paste(COLOURS[colour], (40 * j + 2, 2, 40 * j + 38, 38))
        name = f"images/{k:03d}.png"
        (folder / "images").mkdir(exist_ok=True)
        img.save(folder / name)
        t_ns = int(log.timestamps_ns[col])
        for j, track in enumerate(("red_car", "blue_car", "bike")):
            rows.append(
                {"timestamp_ns": t_ns, "track_id": track, "image": name, "x0": 40 * j + 4, "y0": 4,
                 "x1": 40 * j + 36, "y1": 36, "camera": "ring_front_center", "log_id": log.log_id}
            )  # fmt: skip
    if fmt == "parquet":
        pq.write_table(pa.Table.from_pylist(rows), folder / "crops.parquet")
    else:
        (folder / "crops.json").write_text(json.dumps(rows), encoding="utf-8")
    return folder


RED_CAR = KeywordSet("red car", ("red",), (ObjectPhrase("car", ("red",), "red car"),), ())


@pytest.fixture(scope="module")
def log() -> Log:
    return scene_log()


@pytest.fixture(scope="module")
def frames(log: Log, tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_frames(tmp_path_factory.mktemp("frames") / "cams", log)


def test_the_fake_encoder_satisfies_the_protocol() -> None:
    assert isinstance(MeanColourEncoder(), CropEncoder)


# ---------------------------------------------------------------------- crop tables


def test_crop_tables_are_read_from_parquet_or_json(log: Log, frames: Path, tmp_path: Path) -> None:
    crops = CropTable.read(frames)
    assert len(crops) == 7 * 3  # images at t = 0..6 s, three crops each
    assert set(crops.track_ids) == {"red_car", "blue_car", "bike"}
    assert crops.boxes.shape == (21, 4) and crops.boxes[0].tolist() == [4, 4, 36, 36]
    as_json = CropTable.read(write_frames(tmp_path / "json", log, fmt="json"))
    assert np.array_equal(as_json.timestamps_ns, crops.timestamps_ns)
    assert len(CropTable.read(frames, log_id="another-log")) == 0


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        (None, "no crops.parquet or crops.json"),
        ([{"timestamp_ns": 1, "track_id": "a", "image": "i.png"}], "missing column"),
        (
            [{"timestamp_ns": 1, "track_id": "a", "image": "i.png", "x0": 5, "y0": 0, "x1": 5, "y1": 9}],
            "empty crop",
        ),
        ({"not": "a list"}, "JSON list"),
    ],
)
def test_malformed_crop_tables_are_refused(tmp_path: Path, rows: Any, message: str) -> None:
    if rows is not None:
        (tmp_path / "crops.json").write_text(json.dumps(rows), encoding="utf-8")
    with pytest.raises(CameraFrameError, match=message):
        CropTable.read(tmp_path)


# ---------------------------------------------------------------------- ranking and tracklets


def test_crops_are_ranked_by_similarity_to_the_keywords(frames: Path) -> None:
    crops = CropTable.read(frames)
    ranked = rank_crops(RED_CAR, crops, MeanColourEncoder(), ClipFilterConfig(top_k_crops=5))
    assert ranked.phrases == ("red car",)
    assert ranked.kept.shape == (5,)
    assert set(crops.track_ids[ranked.kept]) == {"red_car"}  # every red crop outranks the others
    assert ranked.scores[ranked.kept].min() > ranked.scores[crops.track_ids == "blue_car"].max()
    # a similarity floor can keep fewer than K
    floor = rank_crops(
        RED_CAR, crops, MeanColourEncoder(), ClipFilterConfig(top_k_crops=20, min_similarity=0.9)
    )
    assert set(crops.track_ids[floor.kept]) == {"red_car"} and floor.kept.size == 7


def test_candidate_tracklets_widen_each_kept_timestamp_by_the_margin(log: Log, frames: Path) -> None:
    crops = CropTable.read(frames)
    ranked = rank_crops(RED_CAR, crops, MeanColourEncoder(), ClipFilterConfig(top_k_crops=2))
    tracklets = candidate_tracklets(log.log_id, crops, ranked, margin_s=0.2)
    assert tracklets.track_ids == ["red_car"]
    kept_s = (tracklets.timestamps_by_track["red_car"] - log.timestamps_ns[0]) * 1e-9
    assert np.allclose(kept_s, [0.0, 1.0])  # ties keep the earlier crops
    cells = candidate_cells(log, tracklets)
    row = log.track_index("red_car")
    assert np.allclose(log.t_s[cells[row]], [0.0, 0.1, 0.2, 0.8, 0.9, 1.0, 1.1, 1.2])
    assert cells.sum() == 8
    with pytest.raises(ValueError, match="applied to log"):
        candidate_cells(scene_log().replace(log_id="other"), tracklets)


def test_the_program_runs_on_the_candidate_tracks_only(log: Log) -> None:
    ctx = LogContext(log)
    tracklets = CandidateTracklets(log.log_id, {"red_car": log.timestamps_ns[[10, 20]]}, margin_s=0.5)
    reduced, cells = restrict_context(ctx, candidate_cells(log, tracklets))
    assert list(reduced.log.track_ids) == ["ego", "red_car"]
    assert (
        cells.shape == (2, log.n_timestamps) and cells[0].sum() == 0 and cells[1].sum() == 21
    )  # 0.5 .. 2.5 s

    def trusted(program: str, context: LogContext, description: str) -> ProgramResult:
        return run_trusted_program(program, context, description=description)

    program = "output_scenario(get_objects_of_category(log_dir, 'VEHICLE'), description)\n"
    report = mine_logs("red car", [ctx], program=program, candidates={log.log_id: tracklets}, runner=trusted)
    assert report.filtered
    m = report.matches[0]
    assert m.referred_track_ids == ["red_car"]  # the ego is a VEHICLE but no candidate
    assert np.allclose((m.timestamps_of("red_car") - log.timestamps_ns[0]) * 1e-9, np.arange(5, 26) / 10)
    # logs without candidates are mined whole
    whole = mine_logs("red car", [ctx], program=program, candidates={}, runner=trusted)
    assert sorted(whole.matches[0].referred_track_ids) == ["blue_car", "ego", "red_car"]


def test_clip_candidates_reads_frames_per_log(log: Log, frames: Path) -> None:
    cfg = MiningConfig(clip=ClipFilterConfig(top_k_crops=3, tracklet_margin_s=0.0))
    # one log's folder given directly, with a fake encoder and given keywords
    out = clip_candidates("red car", [log], frames, cfg, encoder=MeanColourEncoder(), keywords=RED_CAR)
    assert list(out) == [log.log_id] and out[log.log_id].track_ids == ["red_car"]
    # a root with one folder per log id; logs without frames get no entry
    other = scene_log().replace(log_id="no-frames")
    out = clip_candidates(
        "red car", [log, other], frames.parent, cfg, encoder=MeanColourEncoder(), keywords=RED_CAR
    )
    assert list(out) == [log.log_id]


# ---------------------------------------------------------------------- the real CLIP loading code


def test_missing_clip_model_folders_are_named(tmp_path: Path) -> None:
    with pytest.raises(ClipModelError, match="no CLIP model folder given"):
        ClipEncoder.from_pretrained("")
    with pytest.raises(ClipModelError, match="does not exist.*nothing is downloaded"):
        ClipEncoder.from_pretrained(tmp_path / "nope")
    with pytest.raises(ClipModelError, match="no config.json"):
        ClipEncoder.from_pretrained(tmp_path)


def save_tiny_clip(folder: Path) -> Path:
    """A randomly initialised CLIP with 16-wide layers and a character tokenizer, saved like a real one."""
    torch = pytest.importorskip("torch")
    transformers = pytest.importorskip("transformers")
    from transformers.models.clip.image_processing_pil_clip import CLIPImageProcessorPil

    vocab = {"<|startoftext|>": 0, "<|endoftext|>": 1}
    for c in string.ascii_lowercase + string.digits:
        vocab[c] = len(vocab)
        vocab[c + "</w>"] = len(vocab)
    tokenizer = transformers.CLIPTokenizer(vocab=vocab, merges=[])
    images = CLIPImageProcessorPil(size={"shortest_edge": 32}, crop_size={"height": 32, "width": 32})
    layers = {"hidden_size": 16, "intermediate_size": 32, "num_hidden_layers": 1, "num_attention_heads": 2}
    config = transformers.CLIPConfig(
        text_config={**layers, "vocab_size": len(vocab), "max_position_embeddings": 64,
                     "bos_token_id": 0, "eos_token_id": 1, "pad_token_id": 1},
        vision_config={**layers, "image_size": 32, "patch_size": 8},
        projection_dim=8,
    )  # fmt: skip
    torch.manual_seed(0)
    transformers.CLIPModel(config).save_pretrained(folder)
    transformers.CLIPProcessor(image_processor=images, tokenizer=tokenizer).save_pretrained(folder)
    return folder


@pytest.mark.slow  # imports torch and transformers (tens of seconds on a loaded machine)
def test_a_tiny_clip_saved_locally_is_loaded_and_ranks_crops(log: Log, frames: Path, tmp_path: Path) -> None:
    folder = save_tiny_clip(tmp_path / "tiny-clip")
    encoder = ClipEncoder.from_pretrained(folder, batch_size=4)
    text = encoder.encode_text(["a photo of a red car", "a photo of a bicycle"])
    assert text.shape == (2, 8) and np.allclose(np.linalg.norm(text, axis=1), 1.0, atol=1e-5)
    crops = CropTable.read(frames)
    ranked = rank_crops(RED_CAR, crops, encoder, ClipFilterConfig(top_k_crops=4, batch_size=4))
    assert ranked.scores.shape == (21,) and ranked.kept.shape == (4,)
    assert np.all(np.diff(ranked.scores[ranked.kept]) <= 0)
    # identical crops (same colour block in every image) score the same
    red = crops.track_ids == "red_car"
    assert np.ptp(ranked.scores[red]) < 1e-5
    # and the whole coarse stage runs from the configured model path
    cfg = MiningConfig(clip=ClipFilterConfig(model_path=str(folder), top_k_crops=3))
    out = clip_candidates("red car", [log], frames, cfg)
    assert sum(v.size for v in out[log.log_id].timestamps_by_track.values()) <= 3
