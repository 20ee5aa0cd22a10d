#pragma once
// A progress bar's text, apart from the clock and the terminal: the caller passes the
// wall time elapsed (so tests inject it), this file estimates the time remaining and
// formats the line. apps/simulate_cmd.cpp draws it on stderr.
#include <optional>
#include <string>

namespace dmbd {

// The time remaining from the wall time elapsed and the fraction done, assuming the
// rest runs at the average rate so far: elapsed (1 - f) / f. None until the estimate
// means something: before 1 s of wall time and before 2 % of the work (a rate
// measured over less is dominated by start-up), and for a fraction outside (0, 1].
std::optional<double> remaining_seconds(double elapsed_s, double fraction);

// "12 s", "3 min 05 s", "2 h 07 min" (rounded to whole seconds, minutes beyond an
// hour); "--" for none.
std::string format_duration(std::optional<double> seconds);

// The bar's line: "[#########.....................]  30%  balance            12.3 s  ETA 28 s"
// (30 cells, the label cut or padded to 24 characters; "ETA --" while there is no
// estimate).
std::string progress_line(double fraction, const std::string& label, double elapsed_s);

}  // namespace dmbd
