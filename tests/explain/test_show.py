"""Pictures of events: a PNG is written, with or without a vector map, and bad ids are clear errors."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from braking_builders import record, store_with_events, tiny_log

from scenariominer.explain.show import UnknownEventError, render_event, show_event
from scenariominer.llm import HashingEmbedder
from scenariominer.synth import generate_log

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def test_render_writes_a_png_without_importing_pyplot_globally(tmp_path: Path) -> None:
    log = tiny_log("log-a", ["guest"])
    event = record("log-a", "guest", category="cut_in", explanation="It moved in front of the ego. " * 8)
    out = render_event(log, event, tmp_path / "sub" / "event.png", dpi=60)
    data = out.read_bytes()
    assert data.startswith(PNG_MAGIC) and len(data) > 5_000


def test_render_with_a_vector_map(tmp_path: Path) -> None:
    synth = generate_log("right_ped", np.random.default_rng([7, 0]))
    log = synth.log
    guest = synth.label.guest_id
    mid = int(log.timestamps_ns[log.n_timestamps // 2])
    event = record(log.log_id, guest, category="right_ped", closest_ns=mid, guest_category="PEDESTRIAN")
    out = render_event(log, event, tmp_path / "map.png", av2_map=synth.av2_map, dpi=60)
    assert out.read_bytes().startswith(PNG_MAGIC)


def test_show_event_from_store(tmp_path: Path) -> None:
    store = store_with_events(
        tmp_path / "store",
        [record("log-a", "g1", peak_decel_mps2=1.0), record("log-a", "g2", peak_decel_mps2=3.0)],
        HashingEmbedder(16),
    )
    hardest = show_event(store, "log-a", tmp_path / "a.png")
    assert hardest.read_bytes().startswith(PNG_MAGIC)
    chosen = show_event(store, "log-a", tmp_path / "b.png", event_id="g1")
    assert chosen.stat().st_size > 0
    with pytest.raises(UnknownEventError, match="log-a:g1"):
        show_event(store, "log-a", tmp_path / "c.png", event_id="nobody")


def test_importing_the_module_does_not_import_matplotlib() -> None:
    code = "import sys, scenariominer.explain.show; print('matplotlib' in sys.modules)"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "False"
