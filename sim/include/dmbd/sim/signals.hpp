#pragma once
// Reference and disturbance signals of a scenario: functions of time, evaluated at the
// instants a controller samples them (or the plant applies them). Plain data; the YAML
// form is documented in docs/scenario-format.md.
#include <string>
#include <utility>
#include <vector>

namespace dmbd::sim {

struct Source {
  enum class Kind {
    Constant,  // offset
    Steps,     // offset + the value of the last step whose time has passed (t >= t_k)
    Sine,      // offset + amplitude sin(2 pi freq (t - start)) for t >= start
    Chirp,     // offset + amplitude sin(phase(t - start)), exponential sweep f0 -> f1 over duration
  };
  Kind kind = Kind::Constant;
  double offset = 0;
  double amplitude = 0;
  double start_s = 0;
  double duration_s = 0;       // Sine/Chirp: 0 = forever (Sine) ; Chirp: required
  double freq_hz = 0;          // Sine
  double f0_hz = 0, f1_hz = 0; // Chirp
  double ramp_s = 0;           // Sine/Chirp: cosine fade-in and fade-out over this time
  std::vector<std::pair<double, double>> steps;  // Steps: (time s, value) ascending in time
  std::vector<Source> plus;                      // further sources added to this one (a YAML list)

  double value(double t_s) const;          // this source plus those in `plus`
  double own_value(double t_s) const;      // this source alone
  // The instantaneous frequency of a sine or chirp at t (Hz), 0 otherwise.
  double frequency_hz(double t_s) const;
};

// Exponential chirp phase (rad) at time t from its start:
//   2 pi f0 T / ln(f1/f0) (exp(t ln(f1/f0) / T) - 1), instantaneous frequency
//   f0 (f1/f0)^(t/T).
double exponential_chirp_phase(double f0_hz, double f1_hz, double duration_s, double t_s);

}  // namespace dmbd::sim
