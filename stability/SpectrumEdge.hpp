// How many eigenvalues a shift-invert monitor must compute so that its count of unstable ones
// (Re sigma < 0) is not cut off at the edge of the computed set. The set is the `computed`
// eigenvalues nearest the shift: an unstable eigenvalue that moves away from the shift as the
// parameter grows (a Turing mode after its crossing) leaves it, and a stable one moving in takes
// its place, so the count would fall with no change of stability. The set is kept separated: every
// unstable eigenvalue it holds lies strictly inside it, with a stable one farther from the shift;
// where that fails the set grows (doubled, up to a cap) until it holds.
#pragma once

#include <complex>
#include <vector>

namespace keller {

// Whether the unstable values among `values` (eigenvalues found nearest `shift`) are separated
// from the edge of the set: there is none, or some stable value lies farther from the shift than
// every unstable one by more than a relative 1e-6 (a double eigenvalue or a conjugate pair at the
// edge does not separate). A set with fewer values than `computed` (the pencil's finite
// eigenvalues exhausted) is separated.
bool spectrum_edge_separated(const std::vector<std::complex<double>>& values, std::complex<double> shift, int computed);

// The count to compute next at a shift: `computed` while the set is separated, else twice it, at
// most `cap` (returns `computed` when it is already at the cap).
int count_to_separate(const std::vector<std::complex<double>>& values, std::complex<double> shift, int computed,
                      int cap);

}  // namespace keller
