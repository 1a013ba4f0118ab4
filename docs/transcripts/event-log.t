The event log's first lines (docs/architecture.md, "The event log").

  $ . "$TESTDIR/setup.sh"
  $ build/rtm render scenes/spd/balls-1.nff --size 16x16 -q --event-log out/events.log && head -5 out/events.log
  200925 pe0 front_buffer ray0 take 1 primary
  200926 pe0 front_buffer ray0 put search_fifo
  200926 pe0 front_buffer ray1 take 1 primary
  200926 pe0 search ray0 take 4
  200927 pe0 front_buffer ray1 put search_fifo
