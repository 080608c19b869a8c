//! The checks of `[bridge]`: one table for every kind; the keys of another kind are refused.

use super::check::Check;
use super::file::FileBridge;
use super::{limits, Bridge, DampingRule, ModalOptions, SuspensionPreset};
use std::path::Path;
use tbi_dynamics::bridge::SimplySupported;
use tbi_dynamics::InputError;

/// The section keys of `[bridge]`, with their values, in the order they are checked.
type Section = [(&'static str, Option<f64>); 9];

/// One `[bridge]` table under check, with what every kind shares.
struct BridgeCheck<'c, 'b> {
    c: &'c Check<'c>,
    b: &'b FileBridge,
    /// (vertical and lateral, torsional) damping ratios.
    damping: (f64, f64),
    section: Section,
}

impl Check<'_> {
    pub(super) fn bridge(
        &self,
        b: &FileBridge,
        rule: Option<&DampingRule>,
        base_dir: &Path,
    ) -> Result<Bridge, InputError> {
        if b.modes == 0 {
            return Err(self.err("bridge.modes", 0, "must be at least 1"));
        }
        self.at_most("bridge.modes", b.modes, limits::MODES)?;
        let damping = match rule {
            Some(r) => (r.ratio, r.ratio),
            None => {
                let z = self.ratio("bridge.damping_ratio", b.damping_ratio)?;
                let zt = match b.damping_ratio_torsional {
                    Some(z) => self.ratio("bridge.damping_ratio_torsional", z)?,
                    None => z,
                };
                (z, zt)
            }
        };
        for (name, v) in [
            ("bridge.track_eccentricity_m", b.track_eccentricity_m),
            ("bridge.track_height_m", b.track_height_m),
        ] {
            if let Some(v) = v {
                self.finite(name, v)?;
            }
        }
        let section = [
            ("span_m", b.span_m),
            ("youngs_modulus_pa", b.youngs_modulus_pa),
            ("inertia_vertical_m4", b.inertia_vertical_m4),
            ("inertia_lateral_m4", b.inertia_lateral_m4),
            ("shear_modulus_pa", b.shear_modulus_pa),
            ("torsion_constant_m4", b.torsion_constant_m4),
            ("polar_inertia_kg_m", b.polar_inertia_kg_m),
            ("mass_per_length_kg_m", b.mass_per_length_kg_m),
            ("x_start_m", b.x_start_m),
        ];
        let check = BridgeCheck {
            c: self,
            b,
            damping,
            section,
        };
        if b.kind != "beam" {
            check.refuse(&[
                ("spans_m", b.spans_m.is_some()),
                ("sections", b.sections.is_some()),
                ("supports", b.supports.is_some()),
            ])?;
        }
        match b.kind.as_str() {
            "simply_supported" => check.simply_supported(),
            "beam" => check.beam(),
            "modal_file" => check.modal_file(base_dir),
            "suspension" => check.suspension(),
            other => Err(self.err(
                "bridge.kind",
                format!("\"{other}\""),
                "unknown kind; expected \"simply_supported\", \"beam\", \"modal_file\" or \"suspension\"",
            )),
        }
    }
}

impl BridgeCheck<'_, '_> {
    /// Refuses the first key of `keys` that is set: it does not apply to this kind.
    fn refuse(&self, keys: &[(&str, bool)]) -> Result<(), InputError> {
        match keys.iter().find(|(_, set)| *set) {
            Some((name, _)) => Err(self.c.err(
                &format!("bridge.{name}"),
                "(set)",
                &format!("does not apply to kind \"{}\"", self.b.kind),
            )),
            None => Ok(()),
        }
    }

    /// The kinds that interpolate nodal shapes: the interpolation order, no section data.
    fn modal(&self, e_default: f64, h4_default: f64) -> Result<ModalOptions, InputError> {
        let b = self.b;
        let interpolation_points = b.interpolation_points.unwrap_or(4);
        if !(2..=8).contains(&interpolation_points) {
            return Err(self.c.err(
                "bridge.interpolation_points",
                interpolation_points,
                "must lie in 2..=8",
            ));
        }
        let set: Vec<(&str, bool)> = self
            .section
            .iter()
            .map(|(n, v)| (*n, v.is_some()))
            .collect();
        self.refuse(&set)?;
        Ok(ModalOptions {
            modes: b.modes,
            damping_ratio: self.damping.0,
            damping_ratio_torsional: self.damping.1,
            track_eccentricity_m: b.track_eccentricity_m.unwrap_or(e_default),
            track_height_m: b.track_height_m.unwrap_or(h4_default),
            interpolation_points,
        })
    }

    /// Every section value given lies within [`limits::SECTION`]; `positive` first for a beam.
    fn section_within_limits(&self, positive: bool) -> Result<(), InputError> {
        for (name, lo, hi) in limits::SECTION {
            if let Some((_, Some(v))) = self.section.iter().find(|f| f.0 == name) {
                if positive {
                    self.c.positive(&format!("bridge.{name}"), *v)?;
                }
                self.c
                    .within(&format!("bridge.{name}"), *v, (lo, hi), "(SI units)")?;
            }
        }
        Ok(())
    }

    fn simply_supported(&self) -> Result<Bridge, InputError> {
        let (c, b) = (self.c, self.b);
        let required = |name: &str, v: Option<f64>| match v {
            None => Err(c.err(
                &format!("bridge.{name}"),
                "(missing)",
                "is required for kind \"simply_supported\"",
            )),
            Some(v) => c.positive(&format!("bridge.{name}"), v),
        };
        let span_m = required("span_m", b.span_m)?;
        let youngs_modulus_pa = required("youngs_modulus_pa", b.youngs_modulus_pa)?;
        let inertia_vertical_m4 = required("inertia_vertical_m4", b.inertia_vertical_m4)?;
        let mass_per_length_kg_m = required("mass_per_length_kg_m", b.mass_per_length_kg_m)?;
        self.section_within_limits(false)?;
        let tors = [
            b.shear_modulus_pa,
            b.torsion_constant_m4,
            b.polar_inertia_kg_m,
        ];
        let n = tors.iter().filter(|t| t.is_some()).count();
        if n != 0 && n != 3 {
            return Err(c.err(
                "bridge.shear_modulus_pa",
                format!("{:?}", b.shear_modulus_pa),
                "torsion needs shear_modulus_pa, torsion_constant_m4 and polar_inertia_kg_m together",
            ));
        }
        if let Some(x) = b.x_start_m {
            c.finite("bridge.x_start_m", x)?;
        }
        self.refuse(&[
            ("path", b.path.is_some()),
            ("preset", b.preset.is_some()),
            ("interpolation_points", b.interpolation_points.is_some()),
        ])?;
        Ok(Bridge::SimplySupported(SimplySupported {
            span_m,
            youngs_modulus_pa,
            inertia_vertical_m4,
            inertia_lateral_m4: b.inertia_lateral_m4,
            shear_modulus_pa: b.shear_modulus_pa,
            torsion_constant_m4: b.torsion_constant_m4,
            polar_inertia_kg_m: b.polar_inertia_kg_m,
            mass_per_length_kg_m,
            modes: b.modes,
            damping_ratio: self.damping.0,
            damping_ratio_torsional: self.damping.1,
            e_m: b.track_eccentricity_m.unwrap_or(0.0),
            h4_m: b.track_height_m.unwrap_or(0.0),
            x_start_m: b.x_start_m.unwrap_or(0.0),
        }))
    }

    fn beam(&self) -> Result<Bridge, InputError> {
        let (c, b) = (self.c, self.b);
        let spans = b.spans_m.clone().unwrap_or_default();
        if spans.is_empty() {
            return Err(c.err(
                "bridge.spans_m",
                "(missing)",
                "kind \"beam\" needs spans_m = [ … ] (m)",
            ));
        }
        for (i, &l) in spans.iter().enumerate() {
            c.positive(&format!("bridge.spans_m[{i}]"), l)?;
            c.within(&format!("bridge.spans_m[{i}]"), l, (0.1, 1e4), "(m)")?;
        }
        c.at_most("bridge.spans_m (count)", spans.len(), 100)?;
        self.section_within_limits(true)?;
        let sections = self.beam_sections(spans.len())?;
        self.refuse(&[
            ("span_m", b.span_m.is_some()),
            ("inertia_lateral_m4", b.inertia_lateral_m4.is_some()),
            ("shear_modulus_pa", b.shear_modulus_pa.is_some()),
            ("torsion_constant_m4", b.torsion_constant_m4.is_some()),
            ("polar_inertia_kg_m", b.polar_inertia_kg_m.is_some()),
            ("path", b.path.is_some()),
            ("preset", b.preset.is_some()),
        ])?;
        let x_start_m = b.x_start_m.unwrap_or(0.0);
        c.finite("bridge.x_start_m", x_start_m)?;
        let continuous = match b.supports.as_deref().unwrap_or("continuous") {
            "continuous" => true,
            "simply_supported" => false,
            other => {
                return Err(c.err(
                    "bridge.supports",
                    format!("\"{other}\""),
                    "expected \"continuous\" or \"simply_supported\" (a chain of spans)",
                ))
            }
        };
        Ok(Bridge::Beam {
            beam: tbi_fe::beam::ContinuousBeam {
                spans_m: spans,
                sections,
                elements_per_span: 40,
                continuous,
            },
            x_start_m,
            modal: ModalOptions {
                modes: b.modes,
                damping_ratio: self.damping.0,
                damping_ratio_torsional: self.damping.1,
                track_eccentricity_m: b.track_eccentricity_m.unwrap_or(0.0),
                track_height_m: b.track_height_m.unwrap_or(0.0),
                // linear between the nodes of a chain: no smoothing over its hinges
                interpolation_points: b.interpolation_points.unwrap_or(if continuous {
                    4
                } else {
                    2
                }),
            },
        })
    }

    /// One section per span: `bridge.sections[i]`'s own values, else the bridge's.
    fn beam_sections(&self, spans: usize) -> Result<Vec<tbi_fe::beam::SpanSection>, InputError> {
        let (c, b) = (self.c, self.b);
        let given = b.sections.clone().unwrap_or_default();
        if b.sections.is_some() && given.len() != spans {
            return Err(c.err(
                "bridge.sections",
                format!("({} sections)", given.len()),
                &format!("give one section per span ({spans} spans)"),
            ));
        }
        (0..spans)
            .map(|i| {
                let own = given.get(i);
                let pick = |name: &str, mine: Option<f64>, bridge: Option<f64>| match (
                    mine, bridge,
                ) {
                    (Some(v), _) => {
                        let field = format!("bridge.sections[{i}].{name}");
                        c.positive(&field, v)?;
                        if let Some((_, lo, hi)) = limits::SECTION.iter().find(|f| f.0 == name) {
                            c.within(&field, v, (*lo, *hi), "(SI units)")?;
                        }
                        Ok(v)
                    }
                    (None, Some(v)) => Ok(v),
                    (None, None) => Err(c.err(
                        &format!("bridge.{name}"),
                        "(missing)",
                        &format!(
                            "is required for kind \"beam\" (or in every bridge.sections[…]; span {i} has none)"
                        ),
                    )),
                };
                Ok(tbi_fe::beam::SpanSection {
                    youngs_modulus_pa: pick(
                        "youngs_modulus_pa",
                        own.and_then(|s| s.youngs_modulus_pa),
                        b.youngs_modulus_pa,
                    )?,
                    inertia_m4: pick(
                        "inertia_vertical_m4",
                        own.and_then(|s| s.inertia_vertical_m4),
                        b.inertia_vertical_m4,
                    )?,
                    mass_per_length_kg_m: pick(
                        "mass_per_length_kg_m",
                        own.and_then(|s| s.mass_per_length_kg_m),
                        b.mass_per_length_kg_m,
                    )?,
                })
            })
            .collect()
    }

    fn modal_file(&self, base_dir: &Path) -> Result<Bridge, InputError> {
        let Some(path) = self.b.path.clone() else {
            return Err(self.c.err(
                "bridge.path",
                "(missing)",
                "is required for kind \"modal_file\"",
            ));
        };
        let modal = self.modal(0.0, 0.0)?;
        self.refuse(&[("preset", self.b.preset.is_some())])?;
        Ok(Bridge::ModalFile {
            resolved: base_dir.join(&path),
            path,
            modal,
        })
    }

    fn suspension(&self) -> Result<Bridge, InputError> {
        let available = SuspensionPreset::ALL.map(|p| format!("\"{}\"", p.name()));
        let preset = match self.b.preset.as_deref() {
            Some(p) => SuspensionPreset::parse(p).ok_or_else(|| {
                self.c.err(
                    "bridge.preset",
                    format!("\"{p}\""),
                    &format!("unknown preset; available: {}", available.join(", ")),
                )
            })?,
            None => {
                return Err(self.c.err(
                    "bridge.preset",
                    "(missing)",
                    &format!(
                        "is required for kind \"suspension\" (available: {})",
                        available.join(", ")
                    ),
                ))
            }
        };
        let modal = self.modal(2.05, 1.25)?;
        self.refuse(&[("path", self.b.path.is_some())])?;
        Ok(Bridge::Suspension { preset, modal })
    }
}
