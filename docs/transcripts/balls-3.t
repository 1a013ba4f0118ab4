An SPD frame at 256x256 on the default machine (README.md, "Using rtm").

  $ . "$TESTDIR/setup.sh"
  $ build/rtm render scenes/spd-corpus/balls-3.nff --size 256x256 | grep -E '^(balls-3|cycles|bottleneck|error vs reference):'
  balls-3: 256x256, 821 primitives, grid 128x128x14, 1 PE (scanlines, fp32, fast timing); preset default
  cycles: 35435564 (354.356 ms simulated at 10 ns a cycle)
  bottleneck: mac: its entry taken 93.6% of the PEs' working windows
  error vs reference: rmse 0.000871, psnr 61.2 dB, max 0.0758, 126 pixels off by > 1/255, 0 primary hits differ
