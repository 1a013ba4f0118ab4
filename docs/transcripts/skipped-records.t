A warning per kind of skipped NFF record (docs/scene-format.md, "Skipped records").

  $ . "$TESTDIR/setup.sh"
  $ build/rtm render scenes/spd-corpus/teapot-1.nff --size 16x16 -q
  rtm: warning: scenes/spd-corpus/teapot-1.nff:19: skipped 20 'pp' vertex normal records (a normal is zero, or they are not all on one side of the face: shaded flat; lines 19, 23, 27, 31, 35, ...)
  rtm: warning: scenes/spd-corpus/teapot-1.nff:163: skipped 4 degenerate 'pp' records (polygon has zero area; lines 163, 167, 171, 175)
