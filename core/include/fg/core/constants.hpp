// Mathematical constants shared by every layer: one definition each.
#pragma once

namespace fg {

inline constexpr double kPi = 3.14159265358979323846;
//! The float nearest pi, for the float arithmetic of the embedded side.
inline constexpr float kPiF = static_cast<float>(kPi);
static_assert(kPiF == 3.14159265358979f, "the float pi is the float nearest pi");

}  // namespace fg
