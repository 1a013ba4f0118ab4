fp32 against the double-precision reference on three SPD scenes (docs/machine.md, "Accuracy against the reference").

  $ . "$TESTDIR/setup.sh"
  $ for s in balls-2 rings-2 tree-3; do build/rtm render scenes/spd-corpus/$s.nff --size 128x128 --pes 4 | grep '^error vs reference'; done
  error vs reference: rmse 5.85e-06, psnr 104.7 dB, max 0.000433, 0 pixels off by > 1/255, 0 primary hits differ
  error vs reference: rmse 7.11e-05, psnr 83.0 dB, max 0.00716, 2 pixels off by > 1/255, 1 primary hit differs
  error vs reference: rmse 4.92e-07, psnr 126.2 dB, max 1.66e-05, 0 pixels off by > 1/255, 0 primary hits differ
  $ build/rtm render scenes/spd-corpus/rings-2.nff --size 128x128 --pes 4 --set shading_precision=fp64 | grep '^error vs reference'
  error vs reference: rmse 2.39e-08, psnr 152.4 dB, max 5.3e-06, 0 pixels off by > 1/255, 1 primary hit differs
