"""What the package's plots share: matplotlib without a display, and a figure written to a file.

matplotlib is imported on first use, not with this module, so that a Dask worker importing the
package (it only runs FMU tasks) does not need it.
"""

from pathlib import Path
from typing import Any


def pyplot() -> Any:
    """matplotlib.pyplot on the Agg backend: figures are written to files, never shown, so the
    plots run where there is no display (CI, a remote machine)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save(fig: Any, path: str | Path, dpi: int = 110) -> None:
    """Writes `fig` to `path` (the format from its suffix) at `dpi`, its layout tightened, and
    closes it (figures left open hold their memory until the process ends)."""
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    pyplot().close(fig)


def finish_axes(
    ax: Any, xlabel: str, ylabel: str, title: str, columns: int = 1, **grid: Any
) -> None:
    """Labels, title, a light grid (`grid`: its options, e.g. axis="y") and a small legend in
    `columns` columns, for one plot of lines."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3, **grid)
    ax.legend(fontsize=8, ncol=columns)
