"""The convergence study of a user's scene, run by `scripts/converge` (docs/converge/README.md):
`cli` the command line, `study` the ladders and decisions, `runs` one run from one of several
starts (on a Dask worker), `states` the grouping of runs into steady states, `rule` the
convergence rule and its error bound, `cost` the cost model of the budget (`step_cost` measures
it), `report` the outputs. `python -m plateimpact_tools.converge` is the command line."""
