// Hierarchical transport, the module's face: the tree over the patches (patch_tree.h) and the
// links between its nodes, their oracle, tally, push and pull (links.h), and the probe rays that
// tell the oracle where a receiver sees a source whole (visibility_probe.h). Light between groups
// of patches as one link where the oracle says it is accurate enough, so that the transport's
// memory grows with the patches rather than with patches × samples (docs/design/hierarchy.md).
// Not yet used by `radiosity solve`.
#pragma once

#include "hierarchy/block_transport.h"
#include "hierarchy/linked_rows.h"
#include "hierarchy/links.h"
#include "hierarchy/patch_tree.h"
#include "hierarchy/visibility_probe.h"
