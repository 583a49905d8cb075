#pragma once
// Enumerations shared by the scene, the core functions and both backends.
#include <cstdint>

namespace axg::core {

// kDisc: a monolayer culture, somas uniform in the disc of the radius in the plane z = 0.
enum class RegionShape : std::uint8_t { kBall, kSphere, kBox, kDisc };
enum class Sampler : std::uint8_t { kRejection, kNormal, kTrig, kCoordinate };
enum class ContactRule : std::uint8_t { kSwept, kEndpoint };
// kSourceVectorSum: the report's vector rule (unit vectors toward each sensed particle's
// source), which needs knowledge no growth cone has; kept under a name that says so.
enum class GuidanceModel : std::uint8_t { kDirect, kSnr, kVectorSum, kSourceVectorSum };
enum class FieldKind : std::uint8_t { kParticles, kGrid, kAnalytic, kImposed };
// The noise of the growth cone's decision (docs/methods.md §2.6-§2.7), drawn from physical
// parameters and the field's estimate of C and grad C, the same for every field. kBinding
// and kSnapshot are the SNR model's receptor-noise forms f(gamma): counting binding events,
// sqrt(gamma / (1 + gamma)^3), peak at C = K_d / 2; the binomial snapshot of receptor
// occupancy, sqrt(gamma) / (1 + gamma), peak at C = K_d. kCount: the growth cone counts the
// molecules within its sensing radius and turns toward their dipole; the Poisson noise of
// the molecules (not of the simulation particles) is the only noise.
enum class NoiseForm : std::uint8_t { kBinding, kSnapshot, kCount };
// What a growth cone reads from the particle field (particles.hpp, estimate.hpp):
// kEstimate: the converged estimate of C and grad C (two half meshes per cue);
// kMolecules: molecule-resolved count decisions, the count dipole of the particles within
//   r, each particle one molecule (their Poisson noise is the physical noise, exactly);
// kGather: the report's source_vector_sum, from the particles within r.
enum class ParticleSensing : std::uint8_t { kEstimate, kMolecules, kGather };
enum class ImposedProfile : std::uint8_t { kLinear, kExponential };
// What sets an axon's extension: a constant step length (with optional growth-rate
// modulation), or the growth-cone signalling network of signalling.hpp.
enum class GrowthModel : std::uint8_t { kConstant, kSignalling };
enum class CueKind : std::uint8_t { kAttractant, kRepellent };
enum class Motion : std::uint8_t { kBrownian, kBallistic };
enum class GridScheme : std::uint8_t { kExplicit, kImplicit };
enum class GridBoundary : std::uint8_t { kAbsorbing, kReflecting };

// Axon status; the numeric values appear in outputs.
enum class AxonStatus : std::uint8_t { kGrowing = 0, kConnected = 1, kExited = 2, kMaxSteps = 3 };

inline constexpr std::uint32_t kNoNeuron = 0xffffffffu;

}  // namespace axg::core
