#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller {

namespace {
constexpr FluidModel kModels[] = {FluidModel::Newtonian,      FluidModel::OldroydB, FluidModel::FeneP,
                                  FluidModel::Owens,          FluidModel::Giesekus, FluidModel::PttLinear,
                                  FluidModel::PttExponential, FluidModel::FeneCr};
}

const char* to_string(FluidModel m) {
  switch (m) {
    case FluidModel::Newtonian: return "newtonian";
    case FluidModel::OldroydB: return "oldroyd-b";
    case FluidModel::FeneP: return "fene-p";
    case FluidModel::Owens: return "owens";
    case FluidModel::Giesekus: return "giesekus";
    case FluidModel::PttLinear: return "ptt-linear";
    case FluidModel::PttExponential: return "ptt-exponential";
    case FluidModel::FeneCr: return "fene-cr";
  }
  return "?";
}

FluidModel fluid_model_from_string(const std::string& s) {
  std::string names;
  for (FluidModel m : kModels) {
    if (s == to_string(m)) return m;
    names += std::string(names.empty() ? "" : ", ") + to_string(m);
  }
  throw std::invalid_argument("unknown fluid model '" + s + "' (" + names + ")");
}

const char* inadmissible_state(FluidModel model) {
  switch (model) {
    case FluidModel::FeneP: return "FENE-P: tr M reached 3b";
    case FluidModel::FeneCr: return "FENE-CR: tr M reached 3b";
    case FluidModel::PttLinear: return "linear PTT: Y = 1 + epsilon (tr M - 3) reached 0";
    default: return nullptr;
  }
}

}  // namespace keller
