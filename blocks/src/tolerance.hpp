#pragma once
// The check of a rank or cancellation tolerance given by a caller (minimal, minreal).

namespace dmbd::blocks {

// InputError naming `what`'s argument 'tol' unless tol is a finite number >= 0 (a NaN
// tolerance compares false everywhere, and removed every state: the zero system).
void require_tolerance(double tol, const char* what);

}  // namespace dmbd::blocks
