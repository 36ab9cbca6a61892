//! A campaign split at the rows (src/campaign.rs): each record's rows built alone,
//! stacked, and fitted give the identification of the records in one call, bit for
//! bit, for the noise-robust default (its noise model drives the reweighted fit) and for
//! plain rows; rows survive a trip through bytes; parts that cannot be stacked are
//! refused by name.

use std::sync::OnceLock;

use dampid::campaign;
use dampid::prelude::*;
use dampid::prep::steady_state::SteadyStateSettings;
use dampid::reference::{noisy_chain_model, noisy_chain_records, with_displacement_noise};
use dampid::regressor::NoiseTreatment;

/// The noisy chain's 6 records (one per mode), 3 cycles, 0.5 % displacement noise,
/// simulated once for every test here.
fn records() -> &'static [Record] {
    static RECORDS: OnceLock<Vec<Record>> = OnceLock::new();
    RECORDS.get_or_init(|| {
        with_displacement_noise(&noisy_chain_records(3).unwrap(), 0.005, 7).unwrap()
    })
}

/// The default pipeline (harmonic projection, noise-robust rows, propagated weights),
/// windows of one period, with the steady-state check.
fn robust() -> IdentifySettings {
    let mut settings = IdentifySettings::default();
    settings.regressor.windows = WindowSpec::cycles(1).into();
    settings.steady_state = Some(SteadyStateSettings::default());
    settings
}

/// Plain rows: central differences, the noise ignored.
fn plain() -> IdentifySettings {
    let mut settings = robust();
    settings.regressor.velocity = VelocitySource::CentralDifference;
    settings.regressor.noise = NoiseTreatment::Ignore;
    settings
}

/// Each record's rows alone, numbered as the campaign's records.
fn parts(records: &[Record], settings: &IdentifySettings) -> Vec<Regressor> {
    let model = noisy_chain_model();
    (records.iter().enumerate())
        .map(|(k, r)| campaign::rows(&model, std::slice::from_ref(r), k, settings).unwrap())
        .collect()
}

fn json<T: serde::Serialize>(value: &T) -> String {
    serde_json::to_string(value).unwrap()
}

fn fitted(rows: &Regressor, settings: &IdentifySettings) -> Identification {
    identify(
        &ParametricRegressor::linear(&noisy_chain_model(), rows),
        settings,
        &silent,
    )
    .unwrap()
}

/// The stacked rows fit to the same report, bit for bit, as `identify` of the records
/// (coefficients, standard errors, χ², warnings, per-record shares, outliers), whether
/// stacked at once or as a tree of partial stacks; the rows themselves are the same bits.
#[test]
fn stacked_rows_identify_as_the_records_do_bit_for_bit() {
    let records = records();
    for settings in [robust(), plain()] {
        let model = noisy_chain_model();
        let single = identify(
            &ParametricRegressor::linear(&model, records),
            &settings,
            &silent,
        )
        .unwrap();
        let parts = parts(records, &settings);
        let whole = Regressor::stack(parts.clone()).unwrap();
        let (left, right) = parts.split_at(2);
        let tree = Regressor::stack(vec![
            Regressor::stack(left.to_vec()).unwrap(),
            Regressor::stack(right.to_vec()).unwrap(),
        ])
        .unwrap();
        for stacked in [&whole, &tree] {
            assert_eq!(stacked.matrix(), single.regressor.matrix());
            assert_eq!(stacked.rhs(), single.regressor.rhs());
            assert_eq!(stacked.rows(), single.regressor.rows());
            assert_eq!(
                stacked.noise().is_some(),
                settings.regressor.noise != NoiseTreatment::Ignore
            );
            let found = fitted(stacked, &settings);
            assert_eq!(json(&found.report), json(&single.report));
            assert_eq!(found.steady_state, single.steady_state);
            assert!(found.steady_state.is_some());
        }
    }
}

/// Rows through bytes (CBOR, as a worker sends them) fit to the same report.
#[test]
fn rows_survive_a_trip_through_bytes() {
    let records = records();
    let settings = robust();
    let stacked = Regressor::stack(parts(records, &settings)).unwrap();
    let mut bytes = Vec::new();
    ciborium::into_writer(&stacked, &mut bytes).unwrap();
    let back: Regressor = ciborium::from_reader(bytes.as_slice()).unwrap();
    assert_eq!(
        json(&fitted(&back, &settings).report),
        json(&fitted(&stacked, &settings).report)
    );
}

/// Parts of other models or settings, no parts at all, and spans (whose rows carry
/// unknowns of their record) are refused with what differs.
#[test]
fn parts_that_cannot_be_stacked_are_refused_by_name() {
    let records = records();
    let robust_part = parts(&records[..1], &robust()).remove(0);
    let plain_part = parts(&records[1..2], &plain()).remove(0);
    let error = Regressor::stack(vec![robust_part.clone(), plain_part]).unwrap_err();
    assert!(
        matches!(&error, Error::InvalidChoice { name, .. } if name.contains("part 2")),
        "{error}"
    );
    assert!(error.to_string().contains("noise model"), "{error}");

    let other_model = DampingModel::new().with(Term::viscous("c", faer::Mat::identity(6, 6)));
    let other = campaign::rows(&other_model, &records[..1], 1, &robust()).unwrap();
    let error = Regressor::stack(vec![robust_part, other]).unwrap_err();
    assert!(error.to_string().contains("same model"), "{error}");

    let error = Regressor::stack(Vec::new()).unwrap_err();
    assert!(matches!(error, Error::Empty { .. }), "{error}");

    let mut spans = robust();
    spans.regressor.windows =
        dampid::regressor::Windows::Spans(dampid::regressor::SpanWindows::new(1.0));
    let error = campaign::rows(&noisy_chain_model(), &records[..1], 0, &spans).unwrap_err();
    assert!(error.to_string().contains("stored energies"), "{error}");
}
