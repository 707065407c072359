"""The PlateImpact project's Python tools (docs/layout.md has the map):

- `fmu_dask`: the packaged FMU run as Dask tasks (or serially), shared by the studies below;
- `windows`: statistics of a steady state over windows of a recorded run;
- `scene_values`: FMU start values from the scene files and from `name=value` text;
- `references`: the parameter sets, experiments and reference results a packaged FMU carries, for
  fmpy;
- `field`: the FMI 3.0 FMU's deflection field on any mesh through fmpy (Configuration Mode);
- `plotting`: matplotlib without a display, and the helpers the plots share;
- `converge`: the convergence study of a user's scene (`scripts/converge`);
- `studies`: the Python of the studies that regenerate docs/ (plots, generated Markdown, the
  frequency sweep), each run as `python -m plateimpact_tools.studies.NAME`.

Importing the package imports nothing heavy: a Dask worker that unpacks it needs only fmpy and
numpy for the task functions it runs.
"""

import pathlib

# The repository this package sits in (tools/plateimpact_tools/ → the root): where the packaged
# FMU, the scenes and docs/ are found by default.
ROOT = pathlib.Path(__file__).resolve().parents[2]
DEFAULT_FMU = ROOT / "target" / "fmu" / "PlateImpact.fmu"
SCENES = ROOT / "scenes"
