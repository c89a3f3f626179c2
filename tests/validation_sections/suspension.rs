//! VALIDATION.md, section 12: the suspension elements (dampers on series stiffness,
//! force–velocity curves with blow-off, lateral bump stops, per-wheelset contact geometry).
//!
//! Their checks run in their own test files (tests/maxwell.rs, tests/bump_stop.rs,
//! tests/wheelset_profiles.rs), several of them continuations and long simulations that this
//! report does not repeat; the section says what each asserts and the figures its run prints.

/// The section's text, ending with the blank line before the next section.
const SECTION: &str = r#"## 12. Suspension elements: series stiffness, blow-off, bump stops, per-wheelset geometry

Dampers on series stiffness, force–velocity curves with a blow-off, lateral bump stops and per-wheelset contact geometry (docs/model.md §11, §13) have no published numbers to compare with. Each is checked against a closed form, a limit it must reach, or plain simulations that share only the right-hand side with the analysis. The checks run in their own test files, not in this report's: the tables give what each test asserts (its tolerance, on every run) and the figures it prints. `cargo test --release --test FILE TEST -- --nocapture` reproduces a row (FILE and TEST as in its last column).

**Dampers on series stiffness (Maxwell elements).** Element: a damper c in series with its bushes k_s, internal stroke z, c ż = k_s(Δ − z).

| check | independent truth | figure | test |
|---|---|---|---|
| characteristic polynomial of a wheelset whose yaw is held only by a Maxwell pair (k_s = 2 MN/m, c = 100 kN s/m per side) | P(s) = (k_s + c s) det(s²I − sB − A + diag(0, e(s)/I_z)), written from the wheelset's own equations (docs/model.md §8) and the pair's impedance e(s) = 2d²k_s c s/(k_s + c s), against c det(sI − J) of the assembled 5-state Jacobian | asserted below 1e-9 relative at 5 points s at each of 20, 60 and 120 m/s (not printed) | maxwell `a_yaw_held_only_by_a_maxwell_pair_has_the_polynomial_written_by_hand` |
| k_s → ∞ | the rigid damper's V_L, approached like 1/k_s | asserted: the error falls by a factor in [7, 14] per decade, on the wheelset's longitudinal dampers (k_s = 1e7, 1e8, 1e9 N/m) and the bogie's yaw dampers (1e8, 1e9, 1e10 N/m) (not printed) | maxwell `stiff_bushes_tend_to_the_rigid_damper_like_one_over_ks` |
| a car with series-stiff yaw and lateral dampers (32 states) | central differences of f (h = 1e-7); J Φ; f(−x) = −f(x) | asserted: every Jacobian entry within 1e-5 relative (not printed) | maxwell `the_car_with_strokes_has_a_consistent_jacobian_and_is_odd` |
| `secondary.yaw_damper_series_stiffness` on the DTU bogie | the rigid damper | asserted: 1e10 N/m bushes give its V_L to 1e-4, 5 MN/m moves it by more than 1 % (not printed) | maxwell `the_study_key_reaches_the_model_and_bad_values_are_refused` |
| the mode shape's strokes: the passenger car's yaw dampers (300 kN s/m per side, the slope at zero of their curve, on 10 MN/m bushes) at its four crossings (V_L and V_H of each bogie, 2.19 to 3.28 Hz) | the stroke equation (c s + k_s) z = k_s Δ at s = iω: \|z\|/\|Δ\| = k_s/√(k_s² + c²ω²) | 8 strokes, shares 0.851 to 0.924, within 4.6e-12 relative (asserted 1e-9) | maxwell `the_mode_shape_gives_each_stroke_the_closed_form_share_of_its_deflection` |
| the strokes as k_s → ∞ (the bogie's yaw dampers above) | \|z/Δ\| = 1/\|1 + c s/k_s\| tends to 1 like 1/k_s² | 1 − \|z\|/\|Δ\| = 7.18e-4, 7.00e-6, 6.98e-8 at k_s = 1e8, 1e9, 1e10 N/m: ratios 103 and 100 (asserted within [70, 140]) | maxwell `stiff_bushes_leave_the_damper_the_whole_deflection` |

**Force–velocity curves with a blow-off.** The DTU bogie (`studies/dtu-cooperrider-bogie.toml`) with its yaw dampers on 10 MN/m bushes and a relief valve at 3 kN (20 kN s/m beyond):

| check | independent truth | figure | test |
|---|---|---|---|
| the continued cycles on which the valves open | plain simulations of 56 + 4 s from each cycle's start state moved by 0.1 mm | asserted: at the first and the last stable cycle whose largest multiplier is below 0.9, the leading wheelset's amplitude over the last 4 s equals the cycle's within 1e-6 relative, and the damper's force exceeds the 3 kN blow-off (not printed) | maxwell `a_blow_off_damper_cycle_is_the_attractor_of_a_long_simulation` |
| V_NL of the attractor search, below the branch | plain 150 s simulations from the search's state at both ends of its bracket of death | V_NL 84.465 m/s by the search against 129.871 m/s, the branch's lowest stable computed cycle; after 150 s 1.2e-13 m at 84.398 m/s and 4.3 mm at 84.465 m/s (asserted: below 0.1 mm and above 1 mm) | maxwell `blow_off_dampers_hunt_below_the_continued_branch_and_the_report_says_so` |

The bushes, not the valve, make most of that gap: with the same bushes and no valve, the search finds V_NL = 88.63 m/s against the continuation's fold at 143.30 m/s, and with rigid dampers both methods give section 11's fold 4 (docs/vehicles.md, where the bushes are discussed). The passenger car of docs/vehicles.md ("A modern passenger car") runs the first three elements together: yaw dampers with a blow-off on 10 MN/m bushes and secondary bump stops, on S1002/UIC60; no published critical speed is compared there.

**Lateral bump stops.** A stop of free play δ_b each way, then a linear or progressive spring on the lateral deflection of its suspension:

| check | independent truth | figure | test |
|---|---|---|---|
| the force law | the closed form: zero inside the clearance, −k_b(Δ − δ_b sign Δ) beyond, odd; a table's slope changing at its knee; the switching functions zero on the edges and knees | asserted exactly (float equality, 1e-18 on the knees; not printed) | bump_stop `the_force_law_is_a_dead_band_spring_and_odd` |
| a car with progressive primary stops (1 mm, 1 then 5 MN/m) and linear secondary stops (3 mm, 2 MN/m), all engaged | central differences of f; J Φ and J ξ; f(−x) = −f(x) | Jacobian within 1.8e-7 relative (asserted 1e-5) | bump_stop `the_car_with_stops_is_odd_and_its_jacobian_is_exact` |
| the linear analysis | the same bogie without stops | V_L 43.9853981 m/s with and without, identical (asserted 1e-12 relative), and the report's note | bump_stop `the_linear_analysis_is_the_centred_motion_and_says_so` |
| a simulation released beyond the secondary stop's clearance | the switching functions at the integrator's step ends | 15 crossings located, 15 step ends on a switching surface, the worst at 3.5e-18 m (asserted 1e-12 m) | bump_stop `a_simulation_lands_on_the_stops_switching_surfaces` |
| a primary stop on the single wheelset with the flange's clearance and stiffness | the flange (docs/model.md §6), the same law on that layout | `studies/flange-hysteresis.toml`'s two folds (83.990 m/s at 3.23 mm, 83.474 m/s at 4.19 mm) within 2.1e-13 relative in speed and 1.3e-10 in amplitude (asserted 1e-8, 1e-6); the stop's fold curves over the lateral stiffness against the flange's within 5.9e-11 (asserted 1e-4), and against whole diagrams at four points within 2.3e-9 in speed and 1.2e-8 in amplitude (asserted 1e-6, 1e-4) | bump_stop `a_primary_stop_on_the_wheelset_is_the_flange_and_its_fold_curves_equal_diagrams` |
| the DTU bogie with a secondary stop of 2 mm at 20 MN/m | a plain simulation of 56 + 4 s from a stable cycle's start state moved by 0.1 mm | V_L unchanged (215.42058018006503 m/s, identical; asserted 1e-9); V_NL moves from section 11's fold 4 to 150.513 m/s, the speed of its fold 2 (asserted: by more than 10 %); the cycle at 151.779 m/s (largest multiplier 0.884, frame amplitude 2.214 mm, beyond the clearance): simulated amplitude 1.43866 mm, 6.7e-8 relative from the continued one (asserted 1e-6) | bump_stop `a_stop_cycle_of_the_dtu_bogie_is_the_attractor_of_a_long_simulation` |

**Per-wheelset contact geometry** (`[[contact.wheelset]]`):

| check | independent truth | figure | test |
|---|---|---|---|
| the study's own geometry given at every position | the study without the array | bit for bit: f at 20 states of the DTU bogie and of the DTU car, and the bogie's V_L | wheelset_profiles `the_same_geometry_at_every_position_is_the_study_without_the_array_bit_for_bit` |
| a bogie on cones, 0.15 leading and 0.3 trailing, at 30 random states | f(−x) = −f(x); central differences; the trailing wheelset's rows against the forces of a single wheelset on its own table; J ξ and J Φ | odd to 0 (exactly; asserted 1e-14), Jacobian 3.8e-8 (asserted 1e-5), trailing rows 6.7e-15 (asserted 1e-9), tangent and variational products 3.5e-16 (asserted 1e-13) | wheelset_profiles `two_cones_keep_the_odd_symmetry_and_the_exact_jacobian_and_each_row_uses_its_own_table` |
| the trailing conicity 0.15 + ε tending to the leading 0.15 | the uniform bogie's V_L, 93.729555 m/s | V_L differs by 1.898, 0.198 and 0.0199 m/s at ε = 1e-2, 1e-3, 1e-4, linear in ε (asserted: each below a fifth of the previous, the last below 1e-3 V_L); cones (0.15, 0.3) give 72.2587 m/s, swapped 73.3442 m/s | wheelset_profiles `the_critical_speed_tends_to_the_uniform_bogies_as_the_trailing_conicity_tends_to_the_leading` |

"#;

/// Appends the section to the report.
pub fn section(s: &mut String) {
    s.push_str(SECTION);
}
