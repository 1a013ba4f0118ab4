fp32 against the double-precision reference on three SPD scenes (docs/machine.md, "Accuracy against the reference").

  $ . "$TESTDIR/setup.sh"
  $ for s in balls-2 rings-2 tree-3; do build/rtm render scenes/spd-corpus/$s.nff --size 128x128 --pes 4 | grep '^error vs reference'; done
  error vs reference: rmse 1.86e-06, psnr 114.6 dB, max 0.000275, 0 pixels off by > 1/255, 0 primary hits differ
  error vs reference: rmse 4.33e-05, psnr 87.3 dB, max 0.00482, 1 pixels off by > 1/255, 0 primary hits differ
  error vs reference: rmse 3.47e-08, psnr 149.2 dB, max 1.52e-06, 0 pixels off by > 1/255, 0 primary hits differ
  $ build/rtm render scenes/spd-corpus/rings-2.nff --size 128x128 --pes 4 --set shading_precision=fp64 | grep '^error vs reference'
  error vs reference: rmse 1.04e-10, psnr 199.7 dB, max 1.49e-08, 0 pixels off by > 1/255, 0 primary hits differ
