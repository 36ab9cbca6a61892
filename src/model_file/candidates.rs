//! Candidate damping models named on the command line (`dampid compare MODEL --laws
//! linear,coulomb,linear+coulomb,power:1.5`): each candidate is one or more laws of the
//! law registry joined by `+`, each on every DOF to ground with one shared coefficient
//! named after the law; `law:p` sets a power law's exponent p.

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::terms::laws::{LawParameters, Registry};
use crate::terms::{Coefficients, Element, ElementTerm, Term};

/// The model of candidate `spec` (e.g. `linear+power:2.5`) on `dofs` DOFs.
pub fn candidate_model(spec: &str, dofs: usize, laws: &Registry) -> Result<DampingModel> {
    let mut model = DampingModel::new();
    for part in spec.split('+').map(str::trim) {
        let (name, exponent) = match part.split_once(':') {
            Some((name, p)) => {
                let value: f64 = p.trim().parse().map_err(|_| {
                    Error::choice(
                        "candidate law",
                        format!("'{part}'"),
                        "write law:exponent with a number, e.g. power:1.5",
                    )
                })?;
                (name.trim(), Some(value))
            }
            None => (part, None),
        };
        if name.is_empty() {
            return Err(Error::choice(
                "candidate law",
                format!("'{spec}'"),
                "an empty law name; join laws with + and separate candidates with ,",
            ));
        }
        let mut parameters = LawParameters::new();
        if let Some(p) = exponent {
            parameters = parameters.with("exponent", p);
        }
        let law = laws.build(name, &parameters)?;
        let coefficient = match exponent {
            Some(p) => format!("{name}({p})"),
            None => name.to_string(),
        };
        model = model.with(Term::Elements(ElementTerm::new(
            law,
            Element::each_dof(dofs),
            Coefficients::Shared(coefficient),
        )));
    }
    model.validate(dofs)?;
    Ok(model)
}
