A sweep's progress and summary (docs/sweeps.md, "Command line"); wall times and the estimate vary.

  $ . "$TESTDIR/setup.sh"
  $ scripts/sweep scripts/sweep-examples/tiny.yaml --jobs 1 --no-plots
  sweep tiny: 6 runs, 0 already done, results in */out/sweeps/tiny/results.csv (glob)
  [1/6] ok balls-1-32x32-p1-*  cycles 337722  wall * s  eta * (glob)
  [2/6] ok balls-1-32x32-p2-*  cycles 300377  wall * s  eta * (glob)
  [3/6] ok balls-1-32x32-p4-*  cycles 308787  wall * s  eta * (glob)
  [4/6] ok rings-1-32x32-p1-*  cycles 547911  wall * s  eta * (glob)
  [5/6] ok rings-1-32x32-p2-*  cycles 331084  wall * s  eta * (glob)
  [6/6] ok rings-1-32x32-p4-*  cycles 223883  wall * s (glob)
  sweep tiny: 6 runs, 6 rows: 6 ok, 0 missing
    results: */out/sweeps/tiny/results.csv (glob)
    runs:    */out/sweeps/tiny/runs/ (statistics JSON, stderr, images) (glob)
