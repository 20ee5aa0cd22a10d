#pragma once
// A registry of named entries (bus controller types, experiments): the built-in ones given
// once, more added (or replaced) at run time. Not thread-safe against concurrent changes.
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace dmbd {

template <class T>
class Registry {
 public:
  using Entries = std::map<std::string, std::shared_ptr<const T>>;
  explicit Registry(Entries built_in) : entries_(std::move(built_in)) {}

  // Registers (or replaces) `entry` under `name`.
  void add(const std::string& name, std::shared_ptr<const T> entry) { entries_[name] = std::move(entry); }
  // The entry under `name`, or null.
  const T* find(const std::string& name) const {
    const auto it = entries_.find(name);
    return it == entries_.end() ? nullptr : it->second.get();
  }
  // Every name, sorted.
  std::vector<std::string> names() const {
    std::vector<std::string> n;
    for (const auto& e : entries_) n.push_back(e.first);
    return n;
  }

 private:
  Entries entries_;
};

}  // namespace dmbd
