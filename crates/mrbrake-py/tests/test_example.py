"""The example script examples/python/design_study.py runs and passes its own checks."""

import subprocess
import sys


def test_design_study_example_runs(root, tmp_path):
    script = root / "examples" / "python" / "design_study.py"
    done = subprocess.run([sys.executable, str(script), str(tmp_path), "--mesh", "coarse"],
                          capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "fitted current response" in done.stdout
