//! The EN 1991-2 §6.4.6.5(3) comparison that closes a dynamic check: each load effect is
//! designed for the more unfavourable of
//!
//! ```text
//! Φ · (α · LM71)                       (static, with the dynamic factor)
//! (1 + φ'dyn + φ''/2) · HSLM           (dynamic, carefully maintained track; φ'' standard)
//! ```
//!
//! * LM71 (§6.3.2): four 250 kN axles at 1.6 m and 80 kN/m on either side, placed where
//!   the influence line makes them most unfavourable, times α (§6.3.2(3)).
//! * Φ₂ = 1.44/(√L_Φ − 0.2) + 0.82 (carefully maintained track) or
//!   Φ₃ = 2.16/(√L_Φ − 0.2) + 0.73 (standard maintenance), §6.4.5.2; L_Φ from Table 6.2
//!   (the span, or k·L_m for a continuous girder).
//! * φ'' of Annex C eq. (C.4) with n₀ = f₁ and the speed of the train's largest φ'dyn.
//! * The static effects come from exact Euler–Bernoulli influence lines of the beam
//!   ([`tbi_fe::influence`]): the midspan (probe) displacement and bending moment, and the
//!   end support's shear. φ'dyn is the envelope's (displacement) for every effect.
//! * EN 1990 A2.4.4.2.3: the deflection under LM71·Φ at each probe ≤ L/600.
//! * EN 1990 A2.4.4.2.2 (deck twist) needs torsion in the static model: the beam models
//!   carry none, so the twist is stated as not checked.
//!
//! Only beam bridges (`kind = "simply_supported"` or `"beam"`) give the comparison; for the
//! others the report says so.

use super::{Row, Verdict};
use crate::scenario::{Bridge, Scenario};
use tbi_dynamics::en1991;
use tbi_fe::beam::{ContinuousBeam, SpanSection};
use tbi_fe::influence::{axles_max, lm71_max, Effect, StaticBeam};

/// The options of the comparison.
#[derive(Debug, Clone)]
pub struct Options {
    /// LM71's classification factor α (§6.3.2(3)). Default 1.00.
    pub alpha: f64,
    /// Carefully maintained track (Φ₂, φ''/2; default) or standard maintenance (Φ₃, φ'').
    pub careful: bool,
}

impl Options {
    pub fn from_args(args: &crate::design::SweepOptions) -> Result<Options, String> {
        if !en1991::LM71_ALPHAS
            .iter()
            .any(|a| (a - args.alpha).abs() < 1e-12)
        {
            return Err(format!(
                "--alpha {}: LM71's classification factor is one of {} (EN 1991-2 §6.3.2(3))",
                crate::text::num(args.alpha),
                en1991::LM71_ALPHAS
                    .iter()
                    .map(|a| format!("{a:.2}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        let careful = match args.maintenance.as_str() {
            "careful" => true,
            "standard" => false,
            other => {
                return Err(format!(
                    "--maintenance {other}: expected careful (Φ₂, φ''/2) or standard (Φ₃, φ'')"
                ))
            }
        };
        Ok(Options {
            alpha: args.alpha,
            careful,
        })
    }
}

/// One load effect compared.
#[derive(Debug, Clone)]
pub struct EffectRow {
    /// e.g. "bending moment at mid (x = 10 m)".
    pub name: String,
    /// Unit of the values, and the scale from SI to it.
    pub unit: &'static str,
    pub scale: f64,
    pub l_phi_m: f64,
    pub phi2: f64,
    pub phi3: f64,
    /// α · LM71 static effect, SI.
    pub lm71: f64,
    /// Φ · α · LM71, SI.
    pub lm71_phi: f64,
    /// The governing HSLM train, its φ'dyn, φ'' and static effect (SI).
    pub train: String,
    pub phi_dyn: f64,
    pub phi_dd: f64,
    pub hslm_static: f64,
    /// (1 + φ'dyn + φ''/2) · HSLM static (φ'' in full for standard maintenance), SI.
    pub hslm_dynamic: f64,
}

impl EffectRow {
    /// "LM71" or "HSLM": which of the two governs the effect.
    pub fn governs(&self) -> &'static str {
        if self.lm71_phi >= self.hslm_dynamic {
            "LM71"
        } else {
            "HSLM"
        }
    }
}

/// The comparison of a check.
#[derive(Debug, Clone)]
pub struct Comparison {
    pub options: Options,
    pub effects: Vec<EffectRow>,
    /// Per probe: (name, LM71·Φ deflection m, limit L/600 m).
    pub deflections: Vec<(String, f64, f64)>,
    /// Why a part is not checked (the deck twist).
    pub notes: Vec<String>,
}

/// The comparison for the scenario's bridge, or None when it is not a beam.
pub fn compare(
    s: &Scenario,
    bridge: &tbi_dynamics::bridge::ModalBridge,
    trains: &[String],
    rows: &[Row],
    o: &Options,
) -> Result<Option<Comparison>, String> {
    let (beam, x0) = match &s.bridge {
        Bridge::SimplySupported(b) => (
            ContinuousBeam::prismatic(
                vec![b.span_m],
                SpanSection {
                    youngs_modulus_pa: b.youngs_modulus_pa,
                    inertia_m4: b.inertia_vertical_m4,
                    mass_per_length_kg_m: b.mass_per_length_kg_m,
                },
                true,
            ),
            b.x_start_m,
        ),
        Bridge::Beam {
            beam, x_start_m, ..
        } => (beam.clone(), *x_start_m),
        _ => return Ok(None),
    };
    let statics = StaticBeam::new(&beam, 64).map_err(|e| e.to_string())?;
    let f1 = bridge.frequencies_hz[0];
    let mut effects = Vec::new();
    let mut deflections = Vec::new();
    for p in &s.probes {
        let x = p.x_m - x0;
        let span = span_of(&beam.spans_m, x);
        let l_phi = en1991::determinant_length(&beam.spans_m, beam.continuous, span);
        let here = format!("{} (x = {} m)", p.name, crate::text::num(p.x_m));
        for (effect, name, unit, scale) in [
            (
                Effect::Displacement { x_m: x },
                format!("displacement at {here}"),
                "mm",
                1e3,
            ),
            (
                Effect::Moment { x_m: x },
                format!("bending moment at {here}"),
                "kN·m",
                1e-3,
            ),
        ] {
            let row = effect_row(
                &statics, effect, name, unit, scale, l_phi, f1, trains, rows, o,
            )?;
            if unit == "mm" {
                deflections.push((p.name.clone(), row.lm71_phi, beam.spans_m[span] / 600.0));
            }
            effects.push(row);
        }
    }
    let l_phi = en1991::determinant_length(&beam.spans_m, beam.continuous, 0);
    effects.push(effect_row(
        &statics,
        Effect::Reaction { support: 0 },
        "shear at the first support (x = 0)".into(),
        "kN",
        1e-3,
        l_phi,
        f1,
        trains,
        rows,
        o,
    )?);
    Ok(Some(Comparison {
        options: o.clone(),
        effects,
        deflections,
        notes: vec![
            "deck twist (EN 1990 A2.4.4.2.2): not checked — the static beam model carries no torsion".into(),
        ],
    }))
}

/// The span (index) holding x, m from the first support.
fn span_of(spans: &[f64], x: f64) -> usize {
    let mut end = 0.0;
    for (i, l) in spans.iter().enumerate() {
        end += l;
        if x <= end {
            return i;
        }
    }
    spans.len() - 1
}

#[allow(clippy::too_many_arguments)]
fn effect_row(
    statics: &StaticBeam,
    effect: Effect,
    name: String,
    unit: &'static str,
    scale: f64,
    l_phi: f64,
    f1: f64,
    trains: &[String],
    rows: &[Row],
    o: &Options,
) -> Result<EffectRow, String> {
    let line = statics.influence(effect).map_err(|e| e.to_string())?;
    let lm71 = lm71_max(&line, o.alpha, 1.0).value;
    let (phi2, phi3) = (en1991::phi2(l_phi), en1991::phi3(l_phi));
    let phi = if o.careful { phi2 } else { phi3 };
    let mut best: Option<EffectRow> = None;
    for t in trains {
        let Some(r) = rows
            .iter()
            .filter(|r| &r.train == t)
            .max_by(|a, b| a.phi.total_cmp(&b.phi))
        else {
            continue;
        };
        let loads: Vec<(f64, f64)> = tbi_dynamics::hslm::hslm_a(t)?
            .iter()
            .map(|a| (a.offset_m, a.load_n))
            .collect();
        let hslm_static = axles_max(&line, &loads, 1.0).value;
        let phi_dd = en1991::phi_double_prime(l_phi, f1, r.speed_kmh / 3.6);
        let factor = 1.0 + r.phi.max(0.0) + if o.careful { 0.5 * phi_dd } else { phi_dd };
        let candidate = EffectRow {
            name: name.clone(),
            unit,
            scale,
            l_phi_m: l_phi,
            phi2,
            phi3,
            lm71,
            lm71_phi: phi * lm71,
            train: t.clone(),
            phi_dyn: r.phi,
            phi_dd,
            hslm_static,
            hslm_dynamic: factor * hslm_static,
        };
        if best
            .as_ref()
            .is_none_or(|b| candidate.hslm_dynamic > b.hslm_dynamic)
        {
            best = Some(candidate);
        }
    }
    best.ok_or_else(|| "no train to compare".to_string())
}

impl Comparison {
    /// The dynamic factor's name and the φ'' share by the maintenance.
    pub fn phi_name(&self) -> (&'static str, &'static str) {
        if self.options.careful {
            ("Φ₂", "φ''/2")
        } else {
            ("Φ₃", "φ''")
        }
    }

    /// The deflection checks (EN 1990 A2.4.4.2.3).
    pub fn verdicts(&self) -> Vec<Verdict> {
        self.deflections
            .iter()
            .map(|(probe, d, limit)| Verdict {
                name: format!("deflection under LM71·{} at {probe}", self.phi_name().0),
                clause: "EN 1990 A2.4.4.2.3",
                passed: *d <= *limit,
                value: format!("{:.3} mm", 1e3 * d),
                limit: format!("L/600 = {:.3} mm", 1e3 * limit),
                governing: format!("α = {:.2}", self.options.alpha),
                command: None,
            })
            .collect()
    }

    /// The comparison as printed lines.
    pub fn lines(&self) -> Vec<String> {
        let (phi, share) = self.phi_name();
        let mut out = vec![format!(
            "EN 1991-2 §6.4.6.5(3): {phi}·(α·LM71) against (1 + φ'dyn + {share})·HSLM, α = {:.2}, {} track",
            self.options.alpha,
            if self.options.careful {
                "carefully maintained"
            } else {
                "standard maintenance"
            }
        )];
        for e in &self.effects {
            out.push(format!(
                "  {}: LM71 {:.3} {u} × {phi} {:.3} = {:.3} {u}; HSLM {} {:.3} {u} × (1 + {:.3} + {share} with φ'' = {:.3}) = {:.3} {u}; {} governs (L_Φ = {:.3} m, Φ₂ = {:.3}, Φ₃ = {:.3})",
                e.name,
                e.scale * e.lm71,
                if self.options.careful { e.phi2 } else { e.phi3 },
                e.scale * e.lm71_phi,
                e.train,
                e.scale * e.hslm_static,
                e.phi_dyn,
                e.phi_dd,
                e.scale * e.hslm_dynamic,
                e.governs(),
                e.l_phi_m,
                e.phi2,
                e.phi3,
                u = e.unit,
            ));
        }
        out.extend(self.notes.iter().cloned());
        out
    }
}
