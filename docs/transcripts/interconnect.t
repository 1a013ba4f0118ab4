The interconnect's topologies on one frame (docs/machine.md, "The host–PE interconnect").

  $ . "$TESTDIR/setup.sh"
  $ for t in serial "serial --set broadcast=true" "bus --set broadcast=true" "star --set host_ports=4" \
  >     "star --set host_ports=16 --set broadcast=true" "tree --set broadcast=true" \
  >     "tree --set broadcast=true --set host_ports=4 --set tree_fanout=3"; do
  >   echo "link_topology=$t"
  >   build/rtm render scenes/spd/balls-1.nff --size 64x64 --pes 16 --set link_topology=$t | grep -E '^(cycles|interconnect):'
  > done
  link_topology=serial
  cycles: 624703 (6.247 ms simulated at 10 ns)
  interconnect: serial, 1 link: 1317056 bytes, busy 334064 cycles (53.5% of the frame)
  link_topology=serial --set broadcast=true
  cycles: 356758 (3.568 ms simulated at 10 ns)
  interconnect: serial, 1 link: 251276 bytes, busy 66119 cycles (18.5% of the frame)
  link_topology=bus --set broadcast=true
  cycles: 356758 (3.568 ms simulated at 10 ns)
  interconnect: bus, 1 link: 251276 bytes, busy 66119 cycles (18.5% of the frame)
  link_topology=star --set host_ports=4
  cycles: 374710 (3.747 ms simulated at 10 ns)
  interconnect: star, 16 links, 4 host ports: 1317056 bytes, busy 334064 cycles over all links; the busiest, pe0, 20879 (5.6% of the frame)
  link_topology=star --set host_ports=16 --set broadcast=true
  cycles: 315014 (3.150 ms simulated at 10 ns)
  interconnect: star, 16 links, 16 host ports: 1317056 bytes, busy 334064 cycles over all links; the busiest, pe0, 20879 (6.6% of the frame)
  link_topology=tree --set broadcast=true
  cycles: 442542 (4.425 ms simulated at 10 ns)
  interconnect: tree, 16 links, 1 host port: 1745088 bytes, busy 448672 cycles over all links; the busiest, pe0, 66119 (14.9% of the frame)
  link_topology=tree --set broadcast=true --set host_ports=4 --set tree_fanout=3
  cycles: 339520 (3.395 ms simulated at 10 ns)
  interconnect: tree, 16 links, 4 host ports: 1452224 bytes, busy 370256 cycles over all links; the busiest, pe0, 29927 (8.8% of the frame)
