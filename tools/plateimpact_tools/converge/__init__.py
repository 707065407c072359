"""The convergence study of a user's scene, run by `scripts/converge` (docs/converge/README.md):
`study` holds the runs, the ladders and the verdict; `step_cost` measures the cost model the
study's budget estimates use. `python -m plateimpact_tools.converge` is the command line."""
