A local memory of one slow port makes balls-1 memory-bound (docs/memory.md, "Statistics").

  $ . "$TESTDIR/setup.sh"
  $ build/rtm render scenes/spd/balls-1.nff --size 32x32 --search-units 4 --set host_voxel_cycles=0 --set host_ray_cycles=0 --set memory_ports=1 --set memory_latency=64 | grep -E '^(cycles|memory traffic|bottleneck):'
  cycles: 248487 (2.485 ms simulated at 10 ns)
  memory traffic: 63979 requests, 0.6 MiB (timed); stalls 16933, results waiting 3791 cycles (1.7% of the working windows); coefficient RAM hit rate 100.0%
  bottleneck: memory: reads of local memory 86.9% of the units' item-cycles, results waiting for it 1.7% of the PEs' working windows (summed over the units); the busiest port busy 28.0% of the frame
  $ build/rtm render scenes/spd/balls-1.nff --size 32x32 --search-units 4 --set host_voxel_cycles=0 --set host_ray_cycles=0 | grep -E '^(cycles|bottleneck):'
  cycles: 157706 (1.577 ms simulated at 10 ns)
  bottleneck: mac: its entry taken 94.8% of the PEs' working windows
