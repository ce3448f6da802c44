// How many eigenvalues a shift-invert monitor must compute so that its count of unstable ones
// (Re sigma < 0) is not cut off at the edge of the computed set. The set is the `computed`
// eigenvalues nearest the shift: an unstable eigenvalue that moves away from the shift as the
// parameter grows (a Turing mode after its crossing) leaves it, and a stable one moving in takes
// its place, so the count would fall with no change of stability. The set is kept separated: every
// unstable eigenvalue it holds lies strictly inside it, with a stable one farther from the shift;
// where that fails the set grows (doubled, up to a cap) until it holds.
#pragma once

#include <Eigen/Dense>

#include <complex>
#include <cstddef>
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

// The values of one shift's set `found` to add to the spectrum `merged` from the shifts before
// (indices into found, in order): those merged does not hold yet. Two values within 1e-8 (1 +
// |v|) are one eigenvalue found twice (by two shifts); a value `found` holds k times (a multiple
// eigenvalue: the modes of a symmetric domain) is added until merged holds it k times.
std::vector<size_t> values_to_merge(const std::vector<std::complex<double>>& merged,
                                    const std::vector<std::complex<double>>& found);

// Whether an unstable mode of the previous analysis has left the set now computed: the share of
// one of `previous` (the eigenvectors of the unstable eigenvalues there) in the new eigenvectors
// `now`, sum_j |<v, w_j>|^2 / (|v|^2 |w_j|^2), is below 1/2. An unstable eigenvalue becomes stable
// only by crossing the imaginary axis, next to a real shift, where it is inside the set: one that
// is missing has moved beyond the set's edge (a Turing mode after its crossing, overtaken by
// stable modes nearer the shift), and the set must grow.
bool unstable_mode_lost(const std::vector<Eigen::VectorXcd>& previous, const std::vector<Eigen::VectorXcd>& now);

// A shift almost at an eigenvalue (at a located fold or branch point, s = 0 is one) makes the
// shift-invert operator's spectrum span many orders of magnitude: the solver then fails (singular
// J - sB), leaves pairs inaccurate, or converges on the near eigenvalues alone (a double zero at a
// symmetric branch point: 2 pairs of 12 asked). Whether a set (its status ok or not, whether some
// pair is inaccurate, whether J - sB was singular, pairs found and asked) must be computed again
// from a moved shift.
bool needs_moved_shift(bool ok, bool inaccurate, bool singular, int found, int asked);

// How far left to move it: a quarter of the spread |sigma - shift| of the values found, or of the
// last point's set where that is wider (the values found near a double zero span nothing); 1
// where both are 0.
double shift_move(const std::vector<std::complex<double>>& values, std::complex<double> shift, double last_spread);

}  // namespace keller
