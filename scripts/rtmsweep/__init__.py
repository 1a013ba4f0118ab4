"""The sweep tooling: scripts/sweep, scripts/sweep-run and scripts/plot-sweep are thin commands
over these modules (docs/sweeps.md, "The tooling").

columns   the results.csv columns, in order: the one list of the metrics
spec      a sweep spec: parsing, validation, variants, the expansion into jobs and run ids
run       one run (scripts/sweep-run): the rtm command line, its outcome, its row file
results   row files and results.csv: reading, writing, assembling results.csv from the rows
sweep     the whole sweep (scripts/sweep): GNU parallel, resuming, the summary
plot      the plots and the scaling table (scripts/plot-sweep)
"""
