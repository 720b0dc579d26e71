//! The start scene traced as it is: the merit every phase must beat.

use crate::DesignError;
use crate::history::Phase;

use super::{Context, PHASE_PHOTONS};

/// The start's values and merit at [`PHASE_PHOTONS`]; an error where the
/// start itself cannot be traced.
pub fn start(ctx: &mut Context) -> Result<(Vec<f64>, f64), DesignError> {
    let values = ctx.start_values();
    match ctx.judge(Phase::Start, &values, PHASE_PHOTONS) {
        Some(j) => Ok((values, j.merit)),
        None => Err(DesignError::Start(
            ctx.evaluator
                .check(&ctx.start)
                .err()
                .map_or("it is refused".to_owned(), |r| r.to_string()),
        )),
    }
}
