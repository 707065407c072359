//! The stages of one step through a [`Backend`](super::Backend): each borrows the backend and the
//! time levels until the step is over, holds what the step has found so far, and offers only the
//! calls that may follow (the module docs of [`super`] give the order).

use super::maps::FieldMaps;
use crate::contact::{BoundState, PdasReport, PdasSettings};
use crate::error::Error;
use crate::scheme::bounds::ObstacleBounds;
use crate::scheme::sums::FieldSums;
use crate::scheme::{modal, sparse};

/// The fields of the three time levels, in the backend's coordinates.
#[derive(Clone, Debug)]
pub(in crate::scheme) struct TimeLevels {
    /// w_{n−1}.
    pub(in crate::scheme) previous: Vec<f64>,
    /// w_n.
    pub(in crate::scheme) current: Vec<f64>,
    /// w_{n+1} while a step is being solved.
    pub(in crate::scheme) next: Vec<f64>,
}

impl TimeLevels {
    /// Three copies of `field` (a plate at rest).
    pub(in crate::scheme) fn at_rest(field: Vec<f64>) -> TimeLevels {
        TimeLevels {
            previous: field.clone(),
            current: field.clone(),
            next: field,
        }
    }

    /// Shifts n−1 ← n ← n+1.
    pub(in crate::scheme) fn accept(&mut self) {
        std::mem::swap(&mut self.previous, &mut self.current);
        std::mem::swap(&mut self.current, &mut self.next);
    }
}

/// The fields of a step with the maps of their coordinates: what a stage hands on when the
/// backend's part of the step is over (its answer is in `next`), or when the caller solves the
/// step another way and writes `next` itself.
pub(in crate::scheme) struct StepFields<'a> {
    pub(in crate::scheme) maps: FieldMaps<'a>,
    /// w_{n−1}.
    pub(in crate::scheme) previous: &'a [f64],
    /// w_n.
    pub(in crate::scheme) current: &'a [f64],
    /// w_{n+1}.
    pub(in crate::scheme) next: &'a mut [f64],
}

impl<'a> StepFields<'a> {
    pub(super) fn new(
        maps: FieldMaps<'a>,
        previous: &'a [f64],
        current: &'a [f64],
        next: &'a mut [f64],
    ) -> StepFields<'a> {
        StepFields {
            maps,
            previous,
            current,
            next,
        }
    }
}

/// A backend's own part of a stage.
pub(super) enum Engine<M, S> {
    Modal(M),
    Sparse(S),
}

impl<M, S> Engine<M, S> {
    /// The next stage of the modal part; the sparse backend's part is one type at every stage.
    fn modal_into<N>(self, next: impl FnOnce(M) -> N) -> Engine<N, S> {
        match self {
            Engine::Modal(modal) => Engine::Modal(next(modal)),
            Engine::Sparse(sparse) => Engine::Sparse(sparse),
        }
    }
}

/// A step whose unconstrained prediction w* = A⁻¹b is in the next level.
pub(in crate::scheme) struct Prediction<'a> {
    fields: StepFields<'a>,
    sums: FieldSums,
    engine: Engine<modal::Predicted<'a>, sparse::Step<'a>>,
}

/// What the screening of a prediction found.
pub(in crate::scheme) enum Screened<'a> {
    /// The prediction provably satisfies the bounds at every constrained vertex.
    Proven(StepFields<'a>),
    /// Not proven ("not proven", not "violated"): the caller evaluates its values.
    Unproven(Unproven<'a>),
}

impl<'a> Prediction<'a> {
    pub(super) fn new(
        fields: StepFields<'a>,
        sums: FieldSums,
        engine: Engine<modal::Predicted<'a>, sparse::Step<'a>>,
    ) -> Prediction<'a> {
        Prediction {
            fields,
            sums,
            engine,
        }
    }

    /// The prediction's sums (see [`Backend::predict`](super::Backend::predict)).
    pub(in crate::scheme) fn sums(&self) -> FieldSums {
        self.sums
    }

    /// The prediction is w_{n+1} (there is no constraint): the backend's part is over.
    pub(in crate::scheme) fn keep(self) -> StepFields<'a> {
        self.fields
    }

    /// A cheap test of the bounds at every contact point, without computing the values exactly:
    /// the modal backend's reach and levelled screening, the sparse backend's exact test (its
    /// values are sparse rows of w).
    pub(in crate::scheme) fn screen(self, bounds: ObstacleBounds) -> Screened<'a> {
        let Prediction { fields, engine, .. } = self;
        match engine {
            Engine::Modal(predicted) => match predicted.screen(fields.next, bounds) {
                None => Screened::Proven(fields),
                Some(unproven) => Screened::Unproven(Unproven {
                    fields,
                    engine: Engine::Modal(unproven),
                }),
            },
            Engine::Sparse(step) if step.proven_within(fields.next, bounds) => {
                Screened::Proven(fields)
            }
            Engine::Sparse(step) => Screened::Unproven(Unproven {
                fields,
                engine: Engine::Sparse(step),
            }),
        }
    }

    /// The prediction's exact constrained values into `out`, unscreened.
    pub(in crate::scheme) fn exact_values(self, out: &'a mut [f64]) -> Values<'a> {
        let engine = self.engine.modal_into(modal::Predicted::exact);
        Values::exact(self.fields, out, engine)
    }
}

/// A step whose prediction the screening did not prove inside the bounds it was given.
pub(in crate::scheme) struct Unproven<'a> {
    fields: StepFields<'a>,
    engine: Engine<modal::Unproven<'a>, sparse::Step<'a>>,
}

impl<'a> Unproven<'a> {
    /// The constrained values that the contact solve of this step starts from, into `out`: exact
    /// at every point the backend cannot prove inside the screening's `bounds` (those the
    /// screening was given), and at the others possibly a stand-in value inside them, which
    /// [`Values::solve`] replaces by the exact value wherever the solution reaches it. So a
    /// point's value is past a bound exactly where the prediction's is, as a law that bounds the
    /// crossing points needs. A caller that needs every value exact uses
    /// [`Unproven::exact_values`].
    pub(in crate::scheme) fn values(
        self,
        out: &'a mut [f64],
        bounds: ObstacleBounds,
    ) -> Values<'a> {
        self.values_keeping(out, bounds, false)
    }

    /// As [`Unproven::values`], but a large modal basis may also keep a stand-in that it has not
    /// proven inside, past a bound or not, when the prediction certainly crosses a bound
    /// elsewhere: for a contact solve whose bounds do not depend on which points cross (the
    /// position law). Whether the prediction crosses a bound is still read off the values
    /// exactly: they lie within the bounds only if the prediction does.
    pub(in crate::scheme) fn solve_values(
        self,
        out: &'a mut [f64],
        bounds: ObstacleBounds,
    ) -> Values<'a> {
        self.values_keeping(out, bounds, true)
    }

    /// [`Unproven::values`], keeping unproven stand-ins when `keep_unproven`.
    fn values_keeping(
        self,
        out: &'a mut [f64],
        bounds: ObstacleBounds,
        keep_unproven: bool,
    ) -> Values<'a> {
        let Unproven { fields, engine } = self;
        let engine = match engine {
            Engine::Modal(unproven) => {
                Engine::Modal(unproven.values(fields.next, bounds, keep_unproven, out))
            }
            Engine::Sparse(step) => {
                fields.maps.constrained_values(fields.next, out);
                Engine::Sparse(step)
            }
        };
        Values {
            fields,
            values: out,
            engine,
        }
    }

    /// The prediction's exact constrained values into `out`.
    pub(in crate::scheme) fn exact_values(self, out: &'a mut [f64]) -> Values<'a> {
        let engine = self.engine.modal_into(modal::Unproven::exact);
        Values::exact(self.fields, out, engine)
    }
}

/// A step whose prediction's constrained values y* = Bw* are formed (with stand-ins where the
/// backend proved them inside).
pub(in crate::scheme) struct Values<'a> {
    fields: StepFields<'a>,
    values: &'a mut [f64],
    engine: Engine<modal::Valued<'a>, sparse::Step<'a>>,
}

/// What the contact solve of a step gave.
pub(in crate::scheme) enum Solve<'a> {
    /// The exact minimiser is in the next level.
    Solved(Correction<'a>),
    /// The method did not converge: the next level is unspecified, and the caller solves the
    /// step another way.
    Failed {
        report: PdasReport,
        fields: StepFields<'a>,
    },
}

impl<'a> Values<'a> {
    /// The stage with the exact constrained values of the prediction in `fields`, into `out`.
    fn exact(
        fields: StepFields<'a>,
        out: &'a mut [f64],
        engine: Engine<modal::Valued<'a>, sparse::Step<'a>>,
    ) -> Values<'a> {
        fields.maps.constrained_values(fields.next, out);
        Values {
            fields,
            values: out,
            engine,
        }
    }

    /// The values y* at the constrained vertices.
    pub(in crate::scheme) fn values(&self) -> &[f64] {
        self.values
    }

    /// The step's fields and maps.
    pub(in crate::scheme) fn fields(&self) -> &StepFields<'a> {
        &self.fields
    }

    /// Ends the backend's part without a contact solve: the prediction is w_{n+1} (it satisfies
    /// the bounds), or the caller solves the step another way.
    pub(in crate::scheme) fn keep(self) -> StepFields<'a> {
        self.fields
    }

    /// Solves the step's QP (docs/scheme.md §3) from the prediction w* = A⁻¹b, whose constrained
    /// values are these: min ½wᵀAw − bᵀw over `lower` ≤ Bw ≤ `upper`, warm-started from the
    /// contact states `states`, which it updates. An error is a failure of the linear algebra
    /// (a factorisation that lost positive definiteness).
    pub(in crate::scheme) fn solve(
        self,
        lower: &[f64],
        upper: &[f64],
        states: &mut [BoundState],
        settings: &PdasSettings,
    ) -> Result<Solve<'a>, Error> {
        let Values {
            fields,
            values,
            engine,
        } = self;
        let (report, engine) = match engine {
            Engine::Modal(valued) => {
                let (report, corrected) =
                    valued.solve(fields.next, &*values, lower, upper, states, settings);
                (report, corrected.map(Engine::Modal))
            }
            Engine::Sparse(mut step) => {
                let report = step.solve(fields.next, lower, upper, states, settings)?;
                let solved = report.status.is_solved();
                (report, solved.then_some(Engine::Sparse(step)))
            }
        };
        Ok(match engine {
            Some(engine) => Solve::Solved(Correction {
                fields,
                values,
                report,
                engine,
            }),
            None => Solve::Failed { report, fields },
        })
    }
}

/// A step whose contact solve put the exact minimiser w = A⁻¹(b + Bᵀμ) in the next level.
pub(in crate::scheme) struct Correction<'a> {
    fields: StepFields<'a>,
    /// The constrained values the solve started from.
    values: &'a mut [f64],
    report: PdasReport,
    engine: Engine<modal::Corrected<'a>, sparse::Step<'a>>,
}

impl<'a> Correction<'a> {
    /// The solve's report.
    pub(in crate::scheme) fn report(&self) -> &PdasReport {
        &self.report
    }

    /// The multipliers μ (length m).
    pub(in crate::scheme) fn multipliers(&self) -> &[f64] {
        match &self.engine {
            Engine::Modal(corrected) => corrected.multipliers(),
            Engine::Sparse(step) => step.multipliers(),
        }
    }

    /// The step's fields and maps.
    pub(in crate::scheme) fn fields(&self) -> &StepFields<'a> {
        &self.fields
    }

    /// Gives the correction up: the caller solves the step another way into the next level.
    pub(in crate::scheme) fn reject(self) -> StepFields<'a> {
        self.fields
    }

    /// Gives the correction up to solve the step again, with other bounds (an impact law that
    /// bounds more vertices, docs/scheme.md §8): the prediction the solve kept is put back into
    /// the next level, with the values the solve reached (exact wherever it reached a
    /// stand-in), and [`Values::solve`] may follow again.
    pub(in crate::scheme) fn retry(self) -> Values<'a> {
        let Correction {
            fields,
            values,
            engine,
            ..
        } = self;
        let engine = match engine {
            Engine::Modal(corrected) => Engine::Modal(corrected.retry(fields.next, values)),
            Engine::Sparse(step) => {
                step.restore_prediction(fields.next);
                Engine::Sparse(step)
            }
        };
        Values {
            fields,
            values,
            engine,
        }
    }

    /// μᵀB(x − y), x the corrected w_{n+1} and y = w_{n−1}: for the modal backend from the
    /// prediction its solve kept, which this uses up.
    pub(in crate::scheme) fn work(self) -> f64 {
        let StepFields {
            maps,
            previous,
            next,
            ..
        } = self.fields;
        match self.engine {
            Engine::Modal(corrected) => corrected.work(next, previous),
            Engine::Sparse(step) => maps.multiplier_work(next, previous, step.multipliers()),
        }
    }
}
