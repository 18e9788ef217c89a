// The points a run starts from (issue 55). One process builds them all and sets their initial
// stress (Thesis eq. 5.6-5.7). Across processes each builds only its share: the grid's cell
// columns along x are cut where the running count of points passes n r / N (each process counts
// an even run of the columns, the counts are summed), and each process fills its columns, and
// with K0 stresses two columns more on each side, whose points load its own points' K0 columns;
// it keeps its own columns' points. So no process holds much more than its share during the
// set-up; the run then cuts its blocks (repartition_in_blocks).
#pragma once
#include <functional>
#include <string>

#include "core/particles.hpp"
#include "parallel/processes.hpp"
#include "scenario/scenario.hpp"

namespace skred {

// `report` is told when the initial stress begins.
template <int D>
Particles<D> build_points(const ScenarioOf<D>& s, const Processes& procs,
                          const std::function<void(const std::string&)>& report = {});

}  // namespace skred
