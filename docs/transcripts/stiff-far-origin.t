Far from the origin and huge beside tiny: in world coordinates (pe_frame=world) the paper's
arithmetic, the machine latch and the defaults; then the grid's frame and the shading unit in fp64 (docs/numerics.md, "5. Far from the origin, far from the eye, huge and tiny together").

  $ . "$TESTDIR/setup.sh"
  $ build/rtm render scenes/stiff/far-origin.yaml --set pe_frame=world --set recentre=false --set coef_scaling=none --set origin_latch=machine | grep '^error vs reference'
  error vs reference: rmse 0.115, psnr 18.8 dB, max 0.692, 1505 pixels off by > 1/255, 731 primary hits differ
  $ build/rtm render scenes/stiff/far-origin.yaml --set pe_frame=world --set origin_latch=machine | grep '^error vs reference'
  error vs reference: rmse 0.00566, psnr 44.9 dB, max 0.375, 6 pixels off by > 1/255, 2 primary hits differ
  $ build/rtm render scenes/stiff/far-origin.yaml --set pe_frame=world | grep '^error vs reference'
  error vs reference: rmse 0.00206, psnr 53.7 dB, max 0.176, 4 pixels off by > 1/255, 0 primary hits differ
  $ build/rtm render scenes/stiff/far-origin.yaml | grep '^error vs reference'
  error vs reference: rmse 2.68e-07, psnr 131.4 dB, max 1.71e-05, 0 pixels off by > 1/255, 0 primary hits differ
  $ build/rtm render scenes/stiff/far-origin.yaml --set shading_precision=fp64 | grep '^error vs reference'
  error vs reference: rmse 0, psnr inf dB, max 0, 0 pixels off by > 1/255, 0 primary hits differ
  $ build/rtm render scenes/stiff/huge-tiny.yaml --set recentre=false --set coef_scaling=none --set origin_latch=machine | grep '^error vs reference'
  error vs reference: rmse 0.21, psnr 13.6 dB, max 0.66, 1691 pixels off by > 1/255, 1562 primary hits differ
  $ build/rtm render scenes/stiff/huge-tiny.yaml --set origin_latch=machine --set shading_precision=fp64 | grep '^error vs reference'
  error vs reference: rmse 0.0336, psnr 29.5 dB, max 0.611, 46 pixels off by > 1/255, 26 primary hits differ
  $ build/rtm render scenes/stiff/huge-tiny.yaml | grep '^error vs reference'
  error vs reference: rmse 0.0236, psnr 32.6 dB, max 0.49, 221 pixels off by > 1/255, 1 primary hit differs
  $ build/rtm render scenes/stiff/huge-tiny.yaml --set shading_precision=fp64 | grep '^error vs reference'
  error vs reference: rmse 0.00581, psnr 44.7 dB, max 0.49, 1 pixel off by > 1/255, 1 primary hit differs
