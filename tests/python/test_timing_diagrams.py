"""The timing diagrams of docs/timing/ are up to date: their WaveJSON is what the package's
encoders give today (tools/scripts/timing_diagrams.py, which also decodes every drawn frame
back), and each SVG was rendered from the WaveJSON beside it (its first line carries the
WaveJSON's SHA-256). A stale diagram fails here; tools/scripts/timing_diagrams.sh remakes them."""

import hashlib
import os
import re
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TIMING = os.path.join(ROOT, "docs", "timing")
sys.path.insert(0, os.path.join(ROOT, "tools", "scripts"))

import timing_diagrams  # noqa: E402

DIAGRAMS = timing_diagrams.all_diagrams()


def test_every_diagram_has_its_files_and_no_other():
    names = {f[:-5] for f in os.listdir(TIMING) if f.endswith(".json")}
    svgs = {f[:-4] for f in os.listdir(TIMING) if f.endswith(".svg")}
    assert names == set(DIAGRAMS)
    assert svgs == set(DIAGRAMS)


@pytest.mark.parametrize("name", sorted(DIAGRAMS))
def test_wavejson_matches_the_encoders(name):
    with open(os.path.join(TIMING, name + ".json"), encoding="utf-8") as f:
        assert f.read() == timing_diagrams.to_text(DIAGRAMS[name]), (
            "docs/timing/%s.json is stale: run tools/scripts/timing_diagrams.sh" % name)


@pytest.mark.parametrize("name", sorted(DIAGRAMS))
def test_svg_rendered_from_the_wavejson(name):
    with open(os.path.join(TIMING, name + ".json"), "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    with open(os.path.join(TIMING, name + ".svg"), encoding="utf-8") as f:
        first = f.readline()
        rest = f.read()
    m = re.match(r"<!-- WaveDrom rendering of (\S+)\.json, sha256 ([0-9a-f]{64}) ", first)
    assert m and m.group(1) == name, first
    assert m.group(2) == digest, "docs/timing/%s.svg is older than its WaveJSON" % name
    assert rest.lstrip().startswith("<svg") and rest.rstrip().endswith("</svg>")


def test_the_check_mode_finds_a_stale_file(tmp_path):
    assert timing_diagrams.main(["--write", str(tmp_path)]) == 0
    assert timing_diagrams.main(["--check", str(tmp_path)]) == 0
    (tmp_path / "biss_frame.json").write_text("{}\n")
    assert timing_diagrams.main(["--check", str(tmp_path)]) == 1
