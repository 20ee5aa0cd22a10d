#pragma once
// `dmbd draw`: what viz draws of a diagram (viz does not know the diagram module).
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/viz/diagram_drawing.hpp"

namespace dmbd::apps {

// Title "name: description"; inputs and outputs labelled "name [unit]"; each block's
// name, type and fields as written (a tf block's expression alone), its port names
// (a sum's signs); the connections.
viz::DiagramPicture diagram_picture(const diagrams::Diagram& d);

}  // namespace dmbd::apps
