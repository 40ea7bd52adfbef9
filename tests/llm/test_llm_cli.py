"""``scenariominer llm check`` end to end against the loopback OpenAI-compatible server."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from scenariominer.cli import app as root_app

runner = CliRunner()


def write_config(tmp_path: Path, url: str) -> Path:
    p = tmp_path / "c.toml"
    p.write_text(
        f'[llm]\nbackend = "openai"\nbase_url = "{url}"\nmodel = "qwen2.5-coder:1.5b"\n'
        f'cache_dir = "{tmp_path}"\nmax_retries = 0\n'
        '[embedding]\nbackend = "hashing"\nhashing_dim = 64\n'
    )
    return p


def test_check_prints_backend_answer_tokens_and_usage(openai_server, tmp_path):
    result = runner.invoke(
        root_app, ["llm", "check", "-c", str(write_config(tmp_path, openai_server.base_url)), "--embeddings"]
    )
    assert result.exit_code == 0, result.output
    out = result.output
    assert "openai" in out and "qwen2.5-coder:1.5b" in out and openai_server.base_url in out
    assert "'maneuver': 'braking'" in out
    assert "87 prompt + 14 generated" in out
    assert "hashing-64" in out and "dimension" in out
    assert "Model usage" in out
    body = openai_server.bodies("/v1/chat/completions")[0]
    assert body["response_format"]["json_schema"]["name"] == "CheckManeuver"


def test_check_bypasses_the_cache(openai_server, tmp_path):
    cfg = write_config(tmp_path, openai_server.base_url)
    assert runner.invoke(root_app, ["llm", "check", "-c", str(cfg)]).exit_code == 0
    assert runner.invoke(root_app, ["llm", "check", "-c", str(cfg)]).exit_code == 0
    assert len(openai_server.bodies("/v1/chat/completions")) == 2


def test_check_reports_an_unreachable_server(unused_url, tmp_path):
    result = runner.invoke(root_app, ["llm", "check", "-c", str(write_config(tmp_path, unused_url))])
    assert result.exit_code == 2
    assert "error:" in result.output and "cannot reach the server" in result.output


def test_check_reports_an_invalid_config(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text('[llm]\nbackend = "gpt"\n')
    result = runner.invoke(root_app, ["llm", "check", "-c", str(p)])
    assert result.exit_code == 2
    assert "config error" in result.output
