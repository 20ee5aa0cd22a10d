#pragma once
// Reference and disturbance signals of a scenario: functions of time, evaluated at the
// instants a controller samples them (or the plant applies them). Plain data; the YAML
// form is documented in docs/scenario-format.md.
#include <string>
#include <utility>
#include <vector>

namespace dmbd::sim {

// A function of time (a scenario's source: a reference's value, a force's magnitude;
// docs/scenario-format.md, "references"), plus the sources in `plus`. The fields are the
// source map's keys; those a kind does not use are ignored. w below is the cosine fade
// window of ramp_s (1 without one); tau = t - start_s.
struct Source {
  // The source's `type`: constant, steps, sine or chirp.
  enum class Kind {
    Constant,  // offset
    Steps,     // offset + the value of the last step whose time has passed (t >= t_k)
    Sine,      // offset + amplitude w sin(2 pi freq tau) for 0 <= tau <= duration (0: for ever), else offset
    Chirp,     // offset + amplitude w sin(phase(tau)), exponential sweep f0 -> f1 over duration
  };
  Kind kind = Kind::Constant;  // `type`
  double offset = 0;           // added at all times (`offset`, or `value`); a plain number is this alone
  double amplitude = 0;        // Sine/Chirp: the peak value
  double start_s = 0;          // Sine/Chirp: s; before it the source is offset
  double duration_s = 0;       // Sine/Chirp: 0 = forever (Sine) ; Chirp: required
  double freq_hz = 0;          // Sine: the frequency, Hz (> 0)
  // Chirp: the start frequency, Hz (f0_hz > 0).
  double f0_hz = 0, f1_hz = 0; // Chirp: the end frequency, Hz (f1_hz > 0)
  double ramp_s = 0;           // Sine/Chirp: cosine fade-in and fade-out over this time
  std::vector<std::pair<double, double>> steps;  // Steps: (time s, value) ascending in time
  std::vector<Source> plus;                      // further sources added to this one (a YAML list)

  double value(double t_s) const;          // this source plus those in `plus`
  double own_value(double t_s) const;      // this source alone
  // This source's own (not `plus`'s) instantaneous frequency at t (Hz): a sine's freq_hz
  // at any t, a chirp's f0 (f1/f0)^(tau/T) within its sweep, 0 otherwise.
  double frequency_hz(double t_s) const;
};

// Exponential chirp phase (rad) at time t from its start:
//   2 pi f0 T / ln(f1/f0) (exp(t ln(f1/f0) / T) - 1), instantaneous frequency
//   f0 (f1/f0)^(t/T).
double exponential_chirp_phase(double f0_hz, double f1_hz, double duration_s, double t_s);

}  // namespace dmbd::sim
