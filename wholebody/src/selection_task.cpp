// SelectionTask: rows of other tasks (selection_task.hpp).
#include "dmbd/wholebody/selection_task.hpp"

#include <algorithm>
#include <string>

#include "dmbd/base/error.hpp"

namespace dmbd::wholebody {

SelectionTask::SelectionTask(std::vector<std::pair<Task*, int>> rows, int nv)
    : Task(static_cast<int>(rows.size()), nv), rows_(std::move(rows)) {
  for (const auto& [task, row] : rows_) {
    if (!task) throw InputError("selection task: a null source task");
    if (row < 0 || row >= task->dim())
      throw InputError("selection task: row " + std::to_string(row) + " of a task of dimension " + std::to_string(task->dim()));
    if (task->jacobian().cols() != nv) throw InputError("selection task: a source task of another model size");
    if (std::find(sources_.begin(), sources_.end(), task) == sources_.end()) sources_.push_back(task);
  }
}

void SelectionTask::update(const ModelData& data) {
  for (Task* t : sources_) t->update(data);
  for (size_t i = 0; i < rows_.size(); ++i) {
    const Task& t = *rows_[i].first;
    const int r = rows_[i].second;
    const auto k = static_cast<Eigen::Index>(i);
    J_.row(k) = t.jacobian().row(r);
    Jdot_v_[k] = t.jacobian_dot_v()[r];
    e_[k] = t.error()[r];
    edot_[k] = t.error_rate()[r];
    xdd_cmd_[k] = t.command()[r];
  }
}

}  // namespace dmbd::wholebody
