An SPD frame at 256x256 on the default machine (README.md, "Using rtm").

  $ . "$TESTDIR/setup.sh"
  $ build/rtm render scenes/spd-corpus/balls-3.nff --size 256x256 | grep -E '^(balls-3|cycles|bottleneck|error vs reference):'
  balls-3: 256x256, 821 primitives, grid 128x128x14, 1 PE (scanlines, fp32, fast timing)
  cycles: 37085909 (370.859 ms simulated at 10 ns)
  bottleneck: mac: its entry taken 94.0% of the PEs' working windows
  error vs reference: rmse 0.00036, psnr 68.9 dB, max 0.0544, 28 pixels off by > 1/255, 0 primary hits differ
