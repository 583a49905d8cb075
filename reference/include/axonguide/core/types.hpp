#pragma once
// Enumerations shared by the scene, the core functions and both backends.
#include <cstdint>

namespace axg::core {

enum class RegionShape : std::uint8_t { kBall, kSphere, kBox };
enum class Sampler : std::uint8_t { kRejection, kNormal, kTrig, kCoordinate };
enum class ContactRule : std::uint8_t { kSwept, kEndpoint };
// kSourceVectorSum: the report's vector rule (unit vectors toward each sensed particle's
// source), which needs knowledge no growth cone has; kept under a name that says so.
enum class GuidanceModel : std::uint8_t { kDirect, kSnr, kVectorSum, kSourceVectorSum };
enum class FieldKind : std::uint8_t { kParticles, kGrid, kAnalytic, kImposed };
// The receptor-noise form f(gamma) of the SNR (docs/methods.md §2.5): counting binding
// events, sqrt(gamma / (1 + gamma)^3), peak at C = K_d / 2; the binomial snapshot of
// receptor occupancy, sqrt(gamma) / (1 + gamma), peak at C = K_d.
enum class NoiseForm : std::uint8_t { kBinding, kSnapshot };
// What a growth cone derives from the particles within its sensing radius (§2.4):
// kSplit: an unbiased split-sample estimate fed to the SNR decision; kCount: the count
// dipole decides, the count noise being the only noise.
enum class ParticleSensing : std::uint8_t { kSplit, kCount };
enum class ImposedProfile : std::uint8_t { kLinear, kExponential };
// Which pulls the particle gather sums for the vector models (particles.hpp).
enum class Pull : std::uint8_t { kNone, kSensed, kSource };
enum class CueKind : std::uint8_t { kAttractant, kRepellent };
enum class Motion : std::uint8_t { kBrownian, kBallistic };
enum class GridScheme : std::uint8_t { kExplicit, kImplicit };
enum class GridBoundary : std::uint8_t { kAbsorbing, kReflecting };

// Axon status; the numeric values appear in outputs.
enum class AxonStatus : std::uint8_t { kGrowing = 0, kConnected = 1, kExited = 2, kMaxSteps = 3 };

inline constexpr std::uint32_t kNoNeuron = 0xffffffffu;

}  // namespace axg::core
