A local memory of one slow port makes balls-1 memory-bound (docs/memory.md, "Statistics").

  $ . "$TESTDIR/setup.sh"
  $ build/rtm render scenes/spd/balls-1.nff --size 32x32 --search-units 4 --set host_voxel_cycles=0 --set host_ray_cycles=0 --set memory_ports=1 --set memory_latency=64 | grep -E '^(cycles|memory traffic|bottleneck):'
  cycles: 236347 (2.363 ms simulated at 10 ns a cycle)
  memory traffic: 63985 requests, 0.6 MiB (timed); contention stalls 17026 requester-cycles, results waiting 3797 requester-cycles (1.8% of the PEs' working windows); coefficient RAM hit rate 100.0%
  bottleneck: memory: reads of local memory 86.8% of the units' item-cycles, results waiting for it 1.8% of the PEs' working windows (summed over the units); the busiest port busy 29.5% of the frame
  $ build/rtm render scenes/spd/balls-1.nff --size 32x32 --search-units 4 --set host_voxel_cycles=0 --set host_ray_cycles=0 | grep -E '^(cycles|bottleneck):'
  cycles: 139882 (1.399 ms simulated at 10 ns a cycle)
  bottleneck: mac: its entry taken 93.6% of the PEs' working windows
