"""examples/explant_sweep.py --quick draws its figure."""

import subprocess
import sys

import numpy as np

from api_support import SOURCE_DIR


def test_explant_sweep_quick_writes_a_figure(tmp_path):
    out = tmp_path / "fig.png"
    p = subprocess.run([sys.executable, str(SOURCE_DIR / "examples" / "explant_sweep.py"), "--quick", "--out", str(out)],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "wrote" in p.stdout and "steepness 0.2:" in p.stdout
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.image

    img = matplotlib.image.imread(str(out))
    assert img.shape[0] > 200 and img.shape[1] > 300
    rgb = img[..., :3]
    # Not blank: many distinct colours (axes, text, the curve and its bars), and some
    # pixels far from white.
    assert len(np.unique(rgb.reshape(-1, 3), axis=0)) > 20
    assert np.mean(rgb.min(axis=2) < 0.5) > 0.002
