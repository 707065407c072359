"""The Python of the studies that regenerate docs/ (studies/README.md lists them with
their commands): plots and generated Markdown from the CSVs the Rust studies write
(`accuracy_plots`, `statistics_plots`, `damping_plots`, `scale_plots`), figures made from runs
(`restitution`, `damping`) and the frequency sweep of the packaged FMU (`frequency_sweep`)."""
