#pragma once
// What the dashboard needs to draw a study's genotypes as gaits: the robot whose controller
// the genes drive, read from its descriptor (robots/), never assumed.
#include <string>

#include "gaitforge/v1/study.pb.h"

namespace gaitforge::dashboard {

// JSON: {"robot": NAME, "controller": {"kind": K, "actuators": [...], "genes": [{"name",
// "lo", "hi"}, ...], "doc": TEXT}} for a study whose genes drive a robot's controller
// (objective.robot, or a built-in robot the objective is bound to); {"robot": "",
// "controller": null, "note": WHY} otherwise (analytic objectives, calibrations).
std::string StudyRobotJson(const v1::StudySpec& spec);

}  // namespace gaitforge::dashboard
