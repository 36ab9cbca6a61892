//! Units for reports: the model file's optional `[units]` (`length = "m"`, `force = "N"`,
//! `time = "s"`, `angle = "rad"`, `mass = "kg"`), shown in the HTML tables and on the
//! plots' axes. Nothing is converted: the units name what the numbers already are.
//!
//! A coefficient's unit follows from its law, with θ f(v) a force F and the velocity
//! V = L/T (L the length unit, or the angle unit when only that is given):
//!
//! | term | θ = F / f(v) | example |
//! |---|---|---|
//! | linear (viscous), viscous matrix | F·T/L | N·s/m |
//! | quadratic v\|v\| | F·T²/L² | N·s²/m² |
//! | Coulomb sign(v) | F | N |
//! | power \|v\|^p sign(v) | F·(T/L)^p (p to 4 significant digits) | N·(s/m)^1.5 |
//! | stiffness-proportional C = θK | T (K is F/L, C is F·T/L) | s |
//! | mass-proportional C = θM | 1/T (M is F·T²/L) | 1/s |
//! | an expression | F per unit of the expression | N per unit of sign(v)*abs(v)^1.5 |
//! | structural loss factor η (−ηk H\[x\]) | 1 (dimensionless) | 1 |
//!
//! Work (the energy balance's axes) is F·L.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::terms::{MatrixKind, Term};

/// The dimensions a `[units]` section may name.
pub const DIMENSIONS: [&str; 5] = ["length", "force", "time", "angle", "mass"];

/// The units of a model file's quantities, each optional.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Units {
    /// Displacement (e.g. "m").
    pub length: Option<String>,
    /// Force (e.g. "N").
    pub force: Option<String>,
    /// Time (e.g. "s").
    pub time: Option<String>,
    /// Rotation, for angular DOFs (e.g. "rad"); stands for length when length is not given.
    pub angle: Option<String>,
    /// Mass (e.g. "kg"), shown for the non-periodic mode's mass unknowns' table header.
    pub mass: Option<String>,
}

impl Units {
    /// Sets `dimension` to `unit`; [`Error::UnknownName`] for a dimension not in
    /// [`DIMENSIONS`], [`Error::InvalidChoice`] for an empty unit.
    pub fn set(&mut self, dimension: &str, unit: &str) -> Result<()> {
        if unit.trim().is_empty() {
            return Err(Error::choice(dimension, unit, "a unit must not be empty"));
        }
        let slot = match dimension {
            "length" => &mut self.length,
            "force" => &mut self.force,
            "time" => &mut self.time,
            "angle" => &mut self.angle,
            "mass" => &mut self.mass,
            _ => {
                return Err(Error::UnknownName {
                    what: "dimension in [units]".into(),
                    name: dimension.into(),
                    known: DIMENSIONS.join(", "),
                });
            }
        };
        *slot = Some(unit.trim().to_string());
        Ok(())
    }

    /// True when no unit is given.
    pub fn is_empty(&self) -> bool {
        *self == Units::default()
    }

    /// The displacement unit (length, else angle).
    pub fn displacement(&self) -> Option<String> {
        self.length.clone().or_else(|| self.angle.clone())
    }

    /// The velocity unit L/T.
    pub fn velocity(&self) -> Option<String> {
        Some(format!("{}/{}", self.displacement()?, self.time.as_ref()?))
    }

    /// The work unit F·L.
    pub fn work(&self) -> Option<String> {
        Some(format!("{}·{}", self.force.as_ref()?, self.displacement()?))
    }

    /// The unit of the coefficients of `term` (module doc), when the units it needs are
    /// given.
    pub fn coefficient(&self, term: &Term) -> Option<String> {
        let f = self.force.as_ref();
        let l = self.displacement();
        let t = self.time.as_ref();
        let per_velocity = |power: f64| -> Option<String> {
            let (f, l, t) = (f?, l.as_ref()?, t?);
            Some(if power == 1.0 {
                format!("{f}·{t}/{l}")
            } else if power == 2.0 {
                format!("{f}·{t}²/{l}²")
            } else if power == 0.0 {
                f.clone()
            } else {
                format!("{f}·({t}/{l})^{}", crate::format::label(power))
            })
        };
        match term {
            Term::Matrix(m) => match m.kind() {
                MatrixKind::Viscous => per_velocity(1.0),
                MatrixKind::StiffnessProportional => t.cloned(),
                MatrixKind::MassProportional => Some(format!("1/{}", t?)),
            },
            // Bouc–Wen's α and Iwan's K_T multiply a displacement-like state (F/L);
            // Dahl's F_c multiplies ẑ, dimensionless (F).
            Term::History(h) => match h.hysteresis().kind() {
                "dahl" => f.cloned(),
                _ => Some(format!("{}/{}", f?, l?)),
            },
            // a loss factor is dimensionless
            Term::Structural(_) => Some("1".into()),
            Term::Elements(e) => {
                let name = e.law().name();
                match name.as_str() {
                    "linear" => per_velocity(1.0),
                    "quadratic" => per_velocity(2.0),
                    "coulomb" => f.cloned(),
                    _ => match name
                        .strip_prefix("power(")
                        .and_then(|p| p.strip_suffix(')'))
                        .and_then(|p| p.parse::<f64>().ok())
                    {
                        Some(p) => per_velocity(p),
                        None => Some(format!(
                            "{} per unit of {}",
                            f?,
                            crate::format::labels_in(&name)
                        )),
                    },
                }
            }
        }
    }
}

/// `text` with its unit in brackets, "relative velocity [m/s]", or `text` alone.
pub fn with_unit(text: &str, unit: Option<&str>) -> String {
    match unit {
        Some(u) => format!("{text} [{u}]"),
        None => text.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::terms::laws::{Coulomb, Linear, PowerLaw, Quadratic};
    use crate::terms::{Coefficients, Element};

    fn si() -> Units {
        let mut u = Units::default();
        for (d, v) in [("length", "m"), ("force", "N"), ("time", "s")] {
            u.set(d, v).unwrap();
        }
        u
    }

    fn law(l: impl crate::terms::Law + 'static) -> Term {
        Term::on_elements(
            l,
            vec![Element::to_ground(0)],
            Coefficients::Shared("c".into()),
        )
    }

    #[test]
    fn coefficient_units_per_law() {
        let u = si();
        let k = faer::Mat::<f64>::identity(2, 2);
        assert_eq!(u.coefficient(&law(Linear)).unwrap(), "N·s/m");
        assert_eq!(u.coefficient(&law(Quadratic)).unwrap(), "N·s²/m²");
        assert_eq!(u.coefficient(&law(Coulomb)).unwrap(), "N");
        let power = PowerLaw::new(1.5).unwrap();
        assert_eq!(u.coefficient(&law(power)).unwrap(), "N·(s/m)^1.5");
        // An estimated exponent reads rounded (format::label).
        let estimated = PowerLaw::new(2.611665943989249).unwrap();
        assert_eq!(u.coefficient(&law(estimated)).unwrap(), "N·(s/m)^2.612");
        let stiff = Term::stiffness_proportional("beta", k.clone());
        assert_eq!(u.coefficient(&stiff).unwrap(), "s");
        assert_eq!(
            u.coefficient(&Term::mass_proportional("alpha", k.clone()))
                .unwrap(),
            "1/s"
        );
        assert_eq!(u.coefficient(&Term::viscous("c", k)).unwrap(), "N·s/m");
        assert_eq!(u.velocity().unwrap(), "m/s");
        assert_eq!(u.work().unwrap(), "N·m");
        // Missing units: no unit rather than a wrong one.
        assert_eq!(Units::default().coefficient(&law(Linear)), None);
    }

    #[test]
    fn unknown_dimension_is_a_typed_error() {
        let mut u = Units::default();
        assert!(matches!(
            u.set("lenght", "m"),
            Err(Error::UnknownName { .. })
        ));
        assert!(u.set("force", " ").is_err());
        assert!(u.is_empty());
    }
}
