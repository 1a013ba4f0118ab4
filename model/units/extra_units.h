// Units a build adds to the tables beside the machine's own: the compile definition
// RTM_EXTRA_UNITS names a .def file that defines some of the macros below, and
// RTM_EXTRA_UNIT_CLASSES the header of their classes. The normal build defines neither and adds
// nothing; the test of docs/architecture.md, "Adding a unit", adds a pass-through stage this way
// (model/test_unit/pass_through.def).
//   RTM_EXTRA_UNIT_KINDS     UnitKind enumerators, each with a comma, ranked after the search units
//   RTM_EXTRA_UNIT_ROWS      their rows of the unit table (units/unit_table.cpp), each with a comma
//   RTM_EXTRA_UNIT_BUILDS    what each is built of: rows of model/cost/unit_cost.cpp's kBuilds
//   RTM_EXTRA_FIFO_IDS       FifoId enumerators, each with a comma, after the root FIFO
//   RTM_EXTRA_FIFO_ROWS      their rows of the FIFO table (units/fifo_table.cpp), each with a comma
//   RTM_EXTRA_RAY_STAGES(X)  X(kind, class) for each added kind that takes rays from one FIFO and
//                            writes each to its Output: it joins units/ray_stage.h's list, and
//                            both schedulers run it as they run the search units
//   RTM_INTERSECT_WRITER     the kind that writes the intersect FIFO (UnitKind::Search) ...
//   RTM_SEARCH_TO_INTERSECT  ... and the FIFO the search units send rays to for intersection
//                            (FifoId::Intersect): another when a unit stands between them
#pragma once

#ifdef RTM_EXTRA_UNITS
#include RTM_EXTRA_UNITS
#endif

#ifndef RTM_EXTRA_UNIT_KINDS
#define RTM_EXTRA_UNIT_KINDS
#endif
#ifndef RTM_EXTRA_UNIT_ROWS
#define RTM_EXTRA_UNIT_ROWS
#endif
#ifndef RTM_EXTRA_UNIT_BUILDS
#define RTM_EXTRA_UNIT_BUILDS
#endif
#ifndef RTM_EXTRA_FIFO_IDS
#define RTM_EXTRA_FIFO_IDS
#endif
#ifndef RTM_EXTRA_FIFO_ROWS
#define RTM_EXTRA_FIFO_ROWS
#endif
#ifndef RTM_EXTRA_RAY_STAGES
#define RTM_EXTRA_RAY_STAGES(X)
#endif
#ifndef RTM_INTERSECT_WRITER
#define RTM_INTERSECT_WRITER UnitKind::Search
#endif
#ifndef RTM_SEARCH_TO_INTERSECT
#define RTM_SEARCH_TO_INTERSECT FifoId::Intersect
#endif
