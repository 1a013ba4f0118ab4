The interconnect's topologies on one frame (docs/machine.md, "The host–PE interconnect").

  $ . "$TESTDIR/setup.sh"
  $ for t in serial "serial --set broadcast=true" "bus --set broadcast=true" "star --set host_ports=4" \
  >     "star --set host_ports=16 --set broadcast=true" "tree --set broadcast=true" \
  >     "tree --set broadcast=true --set host_ports=4 --set tree_fanout=3"; do
  >   echo "link_topology=$t"
  >   build/rtm render scenes/spd/balls-1.nff --size 64x64 --pes 16 --set link_topology=$t | grep -E '^(cycles|interconnect):'
  > done
  link_topology=serial
  cycles: 620409 (6.204 ms simulated at 10 ns a cycle)
  interconnect: serial, 1 link: 1315904 bytes, busy 333776 cycles (53.8% of the frame)
  link_topology=serial --set broadcast=true
  cycles: 352734 (3.527 ms simulated at 10 ns a cycle)
  interconnect: serial, 1 link: 251204 bytes, busy 66101 cycles (18.7% of the frame)
  link_topology=bus --set broadcast=true
  cycles: 352734 (3.527 ms simulated at 10 ns a cycle)
  interconnect: bus, 1 link: 251204 bytes, busy 66101 cycles (18.7% of the frame)
  link_topology=star --set host_ports=4
  cycles: 370199 (3.702 ms simulated at 10 ns a cycle)
  interconnect: star, 16 links, 4 host ports: 1315904 bytes, busy 333776 cycles over all links; the busiest, pe0, 20861 cycles (5.6% of the frame)
  link_topology=star --set host_ports=16 --set broadcast=true
  cycles: 310842 (3.108 ms simulated at 10 ns a cycle)
  interconnect: star, 16 links, 16 host ports: 1315904 bytes, busy 333776 cycles over all links; the busiest, pe0, 20861 cycles (6.7% of the frame)
  link_topology=tree --set broadcast=true
  cycles: 438446 (4.384 ms simulated at 10 ns a cycle)
  interconnect: tree, 16 links, 1 host port: 1743936 bytes, busy 448384 cycles over all links; the busiest, pe0, 66101 cycles (15.1% of the frame)
  link_topology=tree --set broadcast=true --set host_ports=4 --set tree_fanout=3
  cycles: 335230 (3.352 ms simulated at 10 ns a cycle)
  interconnect: tree, 16 links, 4 host ports: 1451072 bytes, busy 369968 cycles over all links; the busiest, pe0, 29909 cycles (8.9% of the frame)
