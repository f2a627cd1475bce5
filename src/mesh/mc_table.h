#pragma once
// Private: the Marching Cubes case table shared by Marching Cubes and Dual Marching Cubes.
// Built by us (not the classic Lorensen table): ambiguous faces are always resolved the same
// way from both sides (the rule depends only on the face's four corners), so neighbouring
// cells agree and the surface is crack-free and manifold.

#include "vdbmesh/mc_case.h"  // kEdgeCorners, McCase, mc_case()
