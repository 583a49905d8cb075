#pragma once
// Enumerations shared by the scene, the core functions and both backends.
#include <cstdint>

namespace axg::core {

enum class RegionShape : std::uint8_t { kBall, kSphere, kBox };
enum class Sampler : std::uint8_t { kRejection, kNormal, kTrig, kCoordinate };
enum class ContactRule : std::uint8_t { kSwept, kEndpoint };
enum class GuidanceModel : std::uint8_t { kDirect, kSnr, kVectorSum };
enum class FieldKind : std::uint8_t { kParticles, kGrid, kAnalytic };
enum class CueKind : std::uint8_t { kAttractant, kRepellent };
enum class Motion : std::uint8_t { kBrownian, kBallistic };
enum class GridScheme : std::uint8_t { kExplicit, kImplicit };
enum class GridBoundary : std::uint8_t { kAbsorbing, kReflecting };

// Axon status; the numeric values appear in outputs.
enum class AxonStatus : std::uint8_t { kGrowing = 0, kConnected = 1, kExited = 2, kMaxSteps = 3 };

inline constexpr std::uint32_t kNoNeuron = 0xffffffffu;

}  // namespace axg::core
