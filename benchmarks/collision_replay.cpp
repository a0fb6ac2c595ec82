/// Replays the contact inputs recorded by a run with RBFMUSCLE_CONTACT_DUMP=<dir>
/// (core/collision/contact_dump.h): rebuilds the ContactResolver and calls resolve on every
/// recorded frame, timing resolve alone. Prints the collision ms median / max and the max
/// penetration, and writes one line per call (ms, max_penetration_mm, contacts, projections,
/// queries) to <dump>.replay.txt for comparing two builds' answers.
///   collision_replay <dir>/resolver_1.bin [repeats] [respond: -1 as recorded, 0, 1]
#include <algorithm>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "collision/contact_dump.h"
#include "collision/contact_resolver.h"

using namespace rbfmuscle;
using namespace rbfmuscle::contact_dump;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: collision_replay <resolver_n.bin> [repeats] [respond -1|0|1]\n";
    return 2;
  }
  const int repeats = argc > 2 ? std::stoi(argv[2]) : 1;
  const int respond_override = argc > 3 ? std::stoi(argv[3]) : -1;
  std::ifstream in(argv[1], std::ios::binary);
  if (!in) {
    std::cerr << "cannot open " << argv[1] << "\n";
    return 1;
  }
  ContactSettings settings;
  int B = 0;
  readValue(in, settings);
  readValue(in, B);
  std::vector<ContactBone> bones(static_cast<size_t>(B));
  for (ContactBone& bone : bones) {
    int n = 0;
    readValue(in, n);
    bone.name.resize(static_cast<size_t>(n));
    in.read(bone.name.data(), n);
    readMatrix(in, bone.mesh_B.vertices_mm);
    readMatrix(in, bone.mesh_B.triangles);
    Eigen::Matrix4d X;
    readMatrix(in, X);
    bone.X_MB_rest.matrix() = X;
    readValue(in, bone.thickness_mm);
  }
  double offset = 0.0, cutoff = 0.0;
  Eigen::Matrix3Xd centres, probes;
  Eigen::VectorXd weights, shapes;
  Eigen::VectorXi mask;
  readValue(in, offset);
  readValue(in, cutoff);
  readMatrix(in, centres);
  readMatrix(in, weights);
  readMatrix(in, shapes);
  readMatrix(in, probes);
  readMatrix(in, mask);
  const GaussianField rest(offset, centres, weights, shapes, cutoff);
  std::vector<bool> free_centres(static_cast<size_t>(mask.size()));
  for (Eigen::Index k = 0; k < mask.size(); ++k) free_centres[static_cast<size_t>(k)] = mask(k) != 0;
  struct Call {
    bool respond;
    std::vector<Eigen::Isometry3d> X_MB;
    Eigen::Matrix3Xd carried, centres;
    Eigen::VectorXd weights;
    double offset;
  };
  std::vector<Call> calls;
  for (int tag = 0; readValue(in, tag) && tag == 1;) {
    Call c;
    int r = 0;
    readValue(in, r);
    c.respond = r != 0;
    for (int b = 0; b < B; ++b) {
      Eigen::Matrix4d X;
      readMatrix(in, X);
      Eigen::Isometry3d iso;
      iso.matrix() = X;
      c.X_MB.push_back(iso);
    }
    readMatrix(in, c.carried);
    readMatrix(in, c.centres);
    readMatrix(in, c.weights);
    if (!readValue(in, c.offset)) break;
    calls.push_back(std::move(c));
  }
  std::vector<double> ms, cpu_ms;
  std::vector<ContactReport> reports;
  for (int rep = 0; rep < repeats; ++rep) {
    ContactResolver resolver(bones, rest, probes, free_centres, settings);
    GaussianField field = rest;
    for (size_t f = 0; f < calls.size(); ++f) {
      const Call& c = calls[f];
      field.setCentrePositions(c.centres);
      field.setWeights(c.weights);
      field.setOffset(c.offset);
      const bool respond = respond_override < 0 ? c.respond : respond_override != 0;
      timespec t0{}, t1{};
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
      const ContactReport& report = resolver.resolve(c.X_MB, c.carried, field, respond);
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
      cpu_ms.push_back(1e3 * double(t1.tv_sec - t0.tv_sec) + 1e-6 * double(t1.tv_nsec - t0.tv_nsec));
      if (rep == 0) reports.push_back(report);
      ms.push_back(report.ms);
    }
  }
  std::vector<double> sorted = ms, cpu = cpu_ms;
  std::sort(sorted.begin(), sorted.end());
  std::sort(cpu.begin(), cpu.end());
  double pen = 0.0;
  long long projections = 0, queries = 0;
  for (const ContactReport& r : reports) {
    pen = std::max(pen, r.max_penetration_mm);
    projections += r.projections;
    queries += r.probe_queries;
  }
  std::printf("%s: %zu calls x %d, %d probes: resolve ms median %.3f max %.3f (thread CPU ms median %.3f max %.3f) | max penetration %.6f mm | "
              "projections/call %.1f queries/call %.1f\n",
              argv[1], calls.size(), repeats, static_cast<int>(probes.cols()), sorted[sorted.size() / 2], sorted.back(), cpu[cpu.size() / 2], cpu.back(),
              pen, double(projections) / double(reports.size()), double(queries) / double(reports.size()));
  std::ofstream out(std::string(argv[1]) + ".replay.txt");
  for (size_t f = 0; f < reports.size(); ++f)
    out << f << ' ' << reports[f].ms << ' ' << reports[f].max_penetration_mm << ' ' << reports[f].contacts << ' '
        << reports[f].max_penetration_free_mm << ' ' << reports[f].projections << ' ' << reports[f].probe_queries << '\n';
  return 0;
}
