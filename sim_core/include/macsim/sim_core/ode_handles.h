// ODE's opaque handle types, declared as ODE declares them, so that sim_core's public headers
// need none of ODE's: only sim_core's implementation includes ODE.
#pragma once

struct dxWorld;
struct dxSpace;
struct dxBody;
struct dxGeom;
struct dxJoint;
struct dxJointGroup;
struct dJointFeedback;
