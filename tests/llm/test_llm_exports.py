"""The public API of scenariominer.llm, and that importing it stays light."""

from __future__ import annotations

import subprocess
import sys

import scenariominer.llm as llm


def test_every_exported_name_exists_once_and_every_public_class_is_exported():
    assert all(hasattr(llm, name) for name in llm.__all__)
    assert len(set(llm.__all__)) == len(llm.__all__)
    public_classes = {n for n in dir(llm) if n[0].isupper()}
    assert public_classes - set(llm.__all__) == set()


def test_import_does_not_load_heavy_backends():
    code = (
        "import sys, scenariominer.llm; "
        "heavy = [m for m in ('llama_cpp', 'sentence_transformers', 'torch', 'transformers') "
        "if m in sys.modules]; "
        "print(heavy); sys.exit(1 if heavy else 0)"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stdout + result.stderr
