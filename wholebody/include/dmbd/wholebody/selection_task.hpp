#pragma once
// A task made of rows of other tasks (e.g. the paper's torso task: roll and pitch from an
// orientation task, height from a point task): update() updates each source task once at
// the state and copies its chosen rows of J, J̇v, e, ė and ẍ_cmd. The sources' own
// gains make the rows' commands; this task's gains are not used. The sources must
// outlive it. Allocation-free after construction.
#include <utility>
#include <vector>

#include "dmbd/wholebody/task.hpp"

namespace dmbd::wholebody {

class SelectionTask : public Task {
 public:
  // rows: (source task, its row), in this task's row order. Throws InputError for a row
  // out of its task's range or a null task.
  SelectionTask(std::vector<std::pair<Task*, int>> rows, int nv);
  void update(const ModelData& data) override;

 private:
  std::vector<std::pair<Task*, int>> rows_;
  std::vector<Task*> sources_;  // each distinct source once
};

}  // namespace dmbd::wholebody
