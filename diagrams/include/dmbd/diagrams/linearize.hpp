#pragma once
// Linear models of a diagram between any two signals, loops closed through the
// diagram, and the loop transfer at a break point.
#include <string>

#include "dmbd/blocks/sparse_state_space.hpp"
#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::diagrams {

// Signals are named (docs/diagram-format.md, "Signals for analysis"): a diagram input
// or output, `block.port` (an output, or an input: the value arriving there), and
// inside subsystems `subsystem.block.port` / `subsystem.port`.
//
// The model from `from` to `to`: an additive input injected at `from` (every reader
// downstream of that point sees signal + injection; at a diagram input it is the
// input itself), measured at `to` (the value its readers see). Delays are Padé
// approximants in a continuous diagram. The model keeps every state of every block
// (modes the two signals do not see included), balanced, at the diagram's sample time,
// with as many inputs (outputs) as `from` (`to`) is wide. InputError for an unknown
// signal or a numerically singular algebraic loop.
blocks::StateSpace linearize(const Diagram& d, const std::string& from, const std::string& to);

// The model from every diagram input (stacked in file order, each as wide as declared)
// to every output (likewise): the diagram as one block, every state kept, balanced.
// InputError for a numerically singular algebraic loop.
blocks::StateSpace linearize_io(const Diagram& d);
// The loop transfer at a break point: the readers downstream of `at` are fed an
// injected input instead of the signal; L = -(signal before the break)/(injection),
// the negative-feedback convention of the usual margins. InputError as linearize().
blocks::StateSpace loop_transfer(const Diagram& d, const std::string& at);

// The same two models unbalanced, with sparse matrices, in time and memory linear in
// the size of the diagram (apart from the fill-in of chains of direct feedthrough: a
// chain of n lead-lags couples every state to all the earlier ones): for diagrams of
// thousands of blocks, analysed by blocks::Siso.
blocks::SparseStateSpace linearize_sparse(const Diagram& d, const std::string& from, const std::string& to);
// loop_transfer() with sparse matrices, unbalanced, as linearize_sparse().
blocks::SparseStateSpace loop_transfer_sparse(const Diagram& d, const std::string& at);

// Every name `linearize` accepts, for messages and `dmbd draw` (not the shorthand of a
// block's name alone for its only output or input).
std::vector<std::string> signal_names(const Diagram& d);

}  // namespace dmbd::diagrams
