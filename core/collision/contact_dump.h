#pragma once
/// @file
/// Record and replay of a ContactResolver's inputs (constructor and every resolve call) for
/// the collision replay benchmark: set RBFMUSCLE_CONTACT_DUMP=<dir> and each resolver writes
/// <dir>/resolver_<n>.bin (n in construction order). Binary, host byte order.
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace rbfmuscle {
namespace contact_dump {

template <typename M>
void writeMatrix(std::ostream& out, const M& m) {
  const std::int64_t r = m.rows(), c = m.cols();
  out.write(reinterpret_cast<const char*>(&r), sizeof r);
  out.write(reinterpret_cast<const char*>(&c), sizeof c);
  out.write(reinterpret_cast<const char*>(m.data()), static_cast<std::streamsize>(sizeof(typename M::Scalar) * r * c));
}

template <typename M>
bool readMatrix(std::istream& in, M& m) {
  std::int64_t r = 0, c = 0;
  if (!in.read(reinterpret_cast<char*>(&r), sizeof r) || !in.read(reinterpret_cast<char*>(&c), sizeof c)) return false;
  m.resize(r, c);
  return static_cast<bool>(
      in.read(reinterpret_cast<char*>(m.data()), static_cast<std::streamsize>(sizeof(typename M::Scalar) * r * c)));
}

template <typename T>
void writeValue(std::ostream& out, const T& v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof v);
}
template <typename T>
bool readValue(std::istream& in, T& v) {
  return static_cast<bool>(in.read(reinterpret_cast<char*>(&v), sizeof v));
}

}  // namespace contact_dump
}  // namespace rbfmuscle
