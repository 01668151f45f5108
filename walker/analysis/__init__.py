"""Analysis: gait search, continuation, basins, sweeps, measures, robustness."""
