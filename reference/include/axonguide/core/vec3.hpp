#pragma once
// A small 3-vector of doubles. Every operation is + - * / or sqrt, evaluated in the
// order written (no contraction), so host and device agree bit for bit.
#include <cmath>

#include "hd.hpp"

namespace axg::core {

struct Vec3 {
  double x, y, z;
};

AXG_HDI Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
AXG_HDI Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
AXG_HDI Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
AXG_HDI Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
AXG_HDI Vec3 operator*(Vec3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
AXG_HDI Vec3 operator/(Vec3 a, double s) { return {a.x / s, a.y / s, a.z / s}; }
AXG_HDI Vec3& operator+=(Vec3& a, Vec3 b) { return a = a + b; }
AXG_HDI Vec3& operator-=(Vec3& a, Vec3 b) { return a = a - b; }
AXG_HDI bool operator==(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// ((a.x*b.x + a.y*b.y) + a.z*b.z): this association is part of the contract.
AXG_HDI double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
AXG_HDI double norm2(Vec3 a) { return dot(a, a); }
AXG_HDI double norm(Vec3 a) { return std::sqrt(norm2(a)); }
AXG_HDI Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// Unit vector; the caller guarantees |a| > 0.
AXG_HDI Vec3 normalized(Vec3 a) { return a / norm(a); }

}  // namespace axg::core
