"""The command line of the convergence study (`scripts/converge --help`). The study's code lives
in importable modules of `plateimpact_tools.converge`, so that Dask workers run its task
functions by reference to the package rather than as copies pickled from this script."""

from plateimpact_tools.converge.cli import main

main()
