#pragma once
// A diagram flattened into atomic blocks: subsystems dissolved, every block input
// ("reader") resolved to the signal that drives it and to the subsystem boundary
// points it passes through. Linearisation and code generation both work on it.
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::diagrams {

// The diagram flattened into atomic blocks (subsystems dissolved), with every block
// input ("reader") resolved to the signal that drives it and the subsystem boundary
// points it passes through.
//
// It points into the diagram it was made from (and its subsystems): that diagram must
// outlive it. Indices: ctx[0] is the top diagram; signals, points and readers are
// numbered as in their vectors; "atomic" order is context by context, block by block in
// file order.
struct FlatDiagram {
  // One diagram of the hierarchy: the top, or a subsystem block's diagram.
  struct Context {
    const Diagram* d;    // the diagram (not owned)
    std::string prefix;  // "" at the top, "plant." inside block plant
    int parent = -1;     // context index
    // The subsystem block's index in the parent's Diagram::blocks(); -1 at the top.
    int block_in_parent = -1;
    std::vector<int> child;       // per block: child context (subsystems) or -1
    std::vector<int> out_signal;  // per block: first signal id of its outputs (atomic)
  };
  // A value some atomic block or the top diagram produces: a top-level input or an
  // atomic block's output port.
  struct Signal {
    // The full name: the input's name, or "prefix.block.port" ("plant.motor.out").
    std::string name;
    int size = 1;    // width: the number of scalar entries
    int offset = 0;  // in the stacked atomic outputs (top inputs: -1)
    bool top_input = false;  // a top-level diagram input (not produced by a block)
  };
  // How a value reaches a reader: the signal that drives it and the subsystem boundary
  // points on the way.
  struct Route {
    int signal = -1;       // index into signals; -1 until resolved
    std::set<int> points;  // boundary points passed through
  };
  // A consumer of a value: an atomic block's input port, or a top-level output.
  struct Reader {
    // The full name: "prefix.block.port" for an input port, the output's own name.
    std::string name;
    int size = 1;    // width: the number of scalar entries
    int offset = 0;  // in the stacked atomic inputs; top outputs: -1
    Route route;     // the signal it reads and the boundary points on the way
  };
  // A subsystem block dissolves into its blocks; a sampled plant (Block::sampled) stays
  // one atomic block with its discrete model.
  static bool dissolved(const Block& bl) { return bl.type == BlockType::Subsystem && !bl.sampled; }
  std::vector<Context> ctx;  // every diagram of the hierarchy, the top first, depth first
  // Every signal: the top-level inputs in order, then each atomic block's output ports.
  std::vector<Signal> signals;
  std::vector<std::string> points;  // boundary point names ("plant.i", "plant.F")
  std::vector<Reader> readers;      // atomic inputs first, then top outputs
  // The atomic blocks (every block but a subsystem), pointing into their diagrams.
  std::vector<const Block*> atomic;
  // Their full names: the context's prefix + the block's name ("plant.motor").
  std::vector<std::string> atomic_name;
  // Per atomic block: index of its first reader (its input ports, in order, follow).
  std::vector<int> reader_base, signal_base;  // per atomic block: index of its first output signal
  int first_top_output = 0;  // readers from here on are the top-level outputs
  // The total width of the atomic blocks' inputs (the stacked inputs the readers' offsets
  // index).
  int nu = 0, ny = 0;  // the total width of the atomic blocks' outputs (the signals' offsets)

  // Flattens `top`: the contexts, the atomic blocks and their output signals, then every
  // reader with its route resolved. InputError for a loop of plain wires through
  // subsystem boundaries (no block drives it).
  explicit FlatDiagram(const Diagram& top) {
    build_context(&top, "", -1, -1);
    for (size_t i = 0; i < top.inputs().size(); ++i)
      signals.push_back({top.inputs()[i].name, top.inputs()[i].size, -1, true});
    // Atomic blocks and their output signals.
    for (size_t c = 0; c < ctx.size(); ++c) {
      const Diagram& d = *ctx[c].d;
      ctx[c].out_signal.assign(d.blocks().size(), -1);
      for (size_t bi = 0; bi < d.blocks().size(); ++bi) {
        const Block& bl = d.blocks()[bi];
        if (dissolved(bl)) continue;
        atomic.push_back(&bl);
        atomic_name.push_back(ctx[c].prefix + bl.name);
        ctx[c].out_signal[bi] = static_cast<int>(signals.size());
        signal_base.push_back(static_cast<int>(signals.size()));
        for (const Port& p : bl.outputs) {
          signals.push_back({ctx[c].prefix + bl.name + "." + p.name, p.size, ny, false});
          ny += p.size;
        }
      }
    }
    // Readers: every atomic input port, then the top-level outputs.
    for (size_t c = 0; c < ctx.size(); ++c) {
      const Diagram& d = *ctx[c].d;
      for (size_t bi = 0; bi < d.blocks().size(); ++bi) {
        const Block& bl = d.blocks()[bi];
        if (dissolved(bl)) continue;
        reader_base.push_back(static_cast<int>(readers.size()));
        for (size_t k = 0; k < bl.inputs.size(); ++k) {
          Reader r{ctx[c].prefix + bl.name + "." + bl.inputs[k].name, bl.inputs[k].size, nu, {}};
          resolve(static_cast<int>(c), d.drivers(static_cast<int>(bi))[k], r.route, 0);
          readers.push_back(r);
          nu += bl.inputs[k].size;
        }
      }
    }
    first_top_output = static_cast<int>(readers.size());
    for (size_t j = 0; j < top.outputs().size(); ++j) {
      Reader r{top.outputs()[j].name, top.outputs()[j].size, -1, {}};
      resolve(0, top.output_driver(static_cast<int>(j)), r.route, 0);
      readers.push_back(r);
    }
  }

  // Appends the context of diagram d named `prefix`, child of context `parent` through
  // its block `bip`, then (depth first) those of its subsystem blocks. Called by the
  // constructor.
  void build_context(const Diagram* d, const std::string& prefix, int parent, int bip) {
    const int me = static_cast<int>(ctx.size());
    ctx.push_back({d, prefix, parent, bip, {}, {}});
    ctx[static_cast<size_t>(me)].child.assign(d->blocks().size(), -1);
    for (size_t bi = 0; bi < d->blocks().size(); ++bi) {
      const Block& bl = d->blocks()[bi];
      if (!dissolved(bl)) continue;
      const int child = static_cast<int>(ctx.size());
      ctx[static_cast<size_t>(me)].child[bi] = child;
      build_context(bl.subsystem.get(), prefix + bl.name + ".", me, static_cast<int>(bi));
    }
  }

  // The index of the boundary point `name` in points, appended when new.
  int point(const std::string& name) {
    auto it = std::find(points.begin(), points.end(), name);
    if (it != points.end()) return static_cast<int>(it - points.begin());
    points.push_back(name);
    return static_cast<int>(points.size()) - 1;
  }

  // Follow a source upstream through subsystem boundaries to the signal that drives it.
  void resolve(int c, Source src, Route& route, int depth) {
    if (depth > 1000) throw InputError("a loop of plain wires through subsystem boundaries has no block to drive it");
    const Context& cx = ctx[static_cast<size_t>(c)];
    if (src.block == -1) {
      if (cx.parent < 0) {
        route.signal = src.port;
        return;
      }
      const std::string sub = cx.prefix.substr(0, cx.prefix.size() - 1);
      route.points.insert(point(sub + "." + cx.d->inputs()[static_cast<size_t>(src.port)].name));
      const Context& px = ctx[static_cast<size_t>(cx.parent)];
      resolve(cx.parent, px.d->drivers(cx.block_in_parent)[static_cast<size_t>(src.port)], route, depth + 1);
      return;
    }
    const Block& bl = cx.d->blocks()[static_cast<size_t>(src.block)];
    if (!dissolved(bl)) {
      route.signal = cx.out_signal[static_cast<size_t>(src.block)] + src.port;
      return;
    }
    const int child = cx.child[static_cast<size_t>(src.block)];
    route.points.insert(point(cx.prefix + bl.name + "." + bl.outputs[static_cast<size_t>(src.port)].name));
    resolve(child, ctx[static_cast<size_t>(child)].d->output_driver(src.port), route, depth + 1);
  }

  // A named place: a signal, a boundary point, or a reader.
  struct Target {
    // The three kinds of place.
    enum class Kind { Signal, Point, Reader } kind;  // which kind: `index` is into signals, points or readers
    int index;    // into signals, points or readers, by `kind`
    Route route;  // how the value there is formed (for measurement)
    int size;     // width: the number of scalar entries
  };

  // The place `name` denotes, searched in this order: a signal, a reader, a subsystem
  // boundary point (`subsystem.port`), or an atomic block's name alone for its only
  // output (else its only input). InputError for an unknown name, listing up to 12 of
  // names().
  Target find(const std::string& name) {
    for (size_t i = 0; i < signals.size(); ++i)
      if (signals[i].name == name) return {Target::Kind::Signal, static_cast<int>(i), {static_cast<int>(i), {}}, signals[i].size};
    for (size_t i = 0; i < readers.size(); ++i)
      if (readers[i].name == name) return {Target::Kind::Reader, static_cast<int>(i), readers[i].route, readers[i].size};
    // Boundary points: resolve the route of the value at that point.
    for (size_t c = 1; c < ctx.size(); ++c) {
      const Context& cx = ctx[c];
      const std::string sub = cx.prefix.substr(0, cx.prefix.size() - 1);
      const Context& px = ctx[static_cast<size_t>(cx.parent)];
      const Block& bl = px.d->blocks()[static_cast<size_t>(cx.block_in_parent)];
      for (size_t k = 0; k < bl.inputs.size(); ++k)
        if (sub + "." + bl.inputs[k].name == name) {
          Route r;
          r.points.insert(point(name));
          resolve(cx.parent, px.d->drivers(cx.block_in_parent)[k], r, 0);
          return {Target::Kind::Point, point(name), r, bl.inputs[k].size};
        }
      for (size_t k = 0; k < bl.outputs.size(); ++k)
        if (sub + "." + bl.outputs[k].name == name) {
          Route r;
          r.points.insert(point(name));
          resolve(static_cast<int>(c), cx.d->output_driver(static_cast<int>(k)), r, 0);
          return {Target::Kind::Point, point(name), r, bl.outputs[k].size};
        }
    }
    // A block name alone stands for its only output (or, failing that, its only input).
    for (size_t i = 0; i < atomic.size(); ++i)
      if (atomic_name[i] == name) {
        if (atomic[i]->outputs.size() == 1) return find(name + "." + atomic[i]->outputs[0].name);
        if (atomic[i]->inputs.size() == 1) return find(name + "." + atomic[i]->inputs[0].name);
      }
    std::string known;
    int count = 0;
    for (const auto& s : names()) {
      if (count++ == 12) {
        known += ", ...";
        break;
      }
      known += (known.empty() ? "" : ", ") + s;
    }
    throw InputError("unknown signal '" + name + "' (signals: " + known + ")");
  }

  // Every name find() takes: the signals, the boundary points met so far, and the readers
  // not already listed (not the block-name shorthand).
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& s : signals) out.push_back(s.name);
    for (const auto& p : points) out.push_back(p);
    for (const auto& r : readers)
      if (std::find(out.begin(), out.end(), r.name) == out.end()) out.push_back(r.name);
    return out;
  }

  // Whether an input injected at `inj` reaches a reader with route r (reader_index its
  // index in readers, or -1): at a signal, every reader of that signal; at a boundary
  // point, the readers whose route passes through it; at a reader, that reader alone.
  static bool affects(const Target& inj, const Route& r, int reader_index) {
    switch (inj.kind) {
      case Target::Kind::Signal: return r.signal == inj.index;
      case Target::Kind::Point: return r.points.count(inj.index) > 0;
      case Target::Kind::Reader: return reader_index == inj.index;
    }
    return false;
  }
};

}  // namespace dmbd::diagrams
