"""relief.write_png saves a rendered picture without any other package; the README's Python
example runs with nothing but what ``pip install .`` installs."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import relief

ROOT = Path(__file__).resolve().parents[3]


def test_write_png_writes_the_pixels(tmp_path, terrain):
    rgb, _ = relief.render(terrain, 1.0, size=(40, 30))
    relief.write_png(tmp_path / "t.png", rgb)
    assert (tmp_path / "t.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    image = pytest.importorskip("PIL.Image")
    assert np.array_equal(np.asarray(image.open(tmp_path / "t.png")), rgb)


@pytest.mark.parametrize(
    "bad", [np.zeros((4, 5, 3), np.float32), np.zeros((4, 5), np.uint8), np.zeros((4, 5, 4), np.uint8)]
)
def test_write_png_refuses_other_arrays(tmp_path, bad):
    with pytest.raises(relief.ReliefError, match="uint8 array of shape"):
        relief.write_png(tmp_path / "bad.png", bad)


def test_the_readme_example_needs_no_pillow(tmp_path):
    readme = (ROOT / "README.md").read_text()
    example = readme.split("```python\n")[1].split("```")[0]
    # Pillow made unimportable: the example must not need it.
    example = example.replace('"crates/', f'"{ROOT}/crates/')
    script = "import sys\nsys.modules['PIL'] = None\n" + example
    run = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert "EPSG:4326" in run.stdout
    assert (tmp_path / "jacksboro.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
