Far from the origin and huge beside tiny: the paper's arithmetic, the machine latch and the
shading unit in fp64 (docs/numerics.md, "5. Far from the origin, far from the eye, huge and tiny together").

  $ . "$TESTDIR/setup.sh"
  $ build/rtm render scenes/stiff/far-origin.yaml --set recentre=false --set coef_scaling=none --set origin_latch=machine | grep '^error vs reference'
  error vs reference: rmse 0.115, psnr 18.8 dB, max 0.692, 1505 pixels off by > 1/255, 731 primary hits differ
  $ build/rtm render scenes/stiff/far-origin.yaml --set origin_latch=machine | grep '^error vs reference'
  error vs reference: rmse 0.00566, psnr 44.9 dB, max 0.375, 6 pixels off by > 1/255, 2 primary hits differ
  $ build/rtm render scenes/stiff/far-origin.yaml | grep '^error vs reference'
  error vs reference: rmse 0.00206, psnr 53.7 dB, max 0.176, 4 pixels off by > 1/255, 0 primary hits differ
  $ build/rtm render scenes/stiff/far-origin.yaml --set shading_precision=fp64 | grep '^error vs reference'
  error vs reference: rmse 0, psnr inf dB, max 0, 0 pixels off by > 1/255, 0 primary hits differ
  $ build/rtm render scenes/stiff/huge-tiny.yaml --set recentre=false --set coef_scaling=none --set origin_latch=machine | grep '^error vs reference'
  error vs reference: rmse 0.161, psnr 15.9 dB, max 0.602, 839 pixels off by > 1/255, 820 primary hits differ
  $ build/rtm render scenes/stiff/huge-tiny.yaml --set origin_latch=machine --set shading_precision=fp64 | grep '^error vs reference'
  error vs reference: rmse 0.029, psnr 30.8 dB, max 0.602, 28 pixels off by > 1/255, 21 primary hits differ
  $ build/rtm render scenes/stiff/huge-tiny.yaml | grep '^error vs reference'
  error vs reference: rmse 0.0296, psnr 30.6 dB, max 0.46, 119 pixels off by > 1/255, 0 primary hits differ
  $ build/rtm render scenes/stiff/huge-tiny.yaml --set shading_precision=fp64 | grep '^error vs reference'
  error vs reference: rmse 0.000882, psnr 61.1 dB, max 0.0543, 3 pixels off by > 1/255, 0 primary hits differ
