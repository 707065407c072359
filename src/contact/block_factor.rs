//! The factorisation of the active block W_𝒜𝒜 of a Delassus operator, kept in step with a working
//! set 𝒜 that changes by a few indices at a time.
//!
//! W_𝒜𝒜 = L D Lᵀ (L unit lower triangular, D diagonal and positive since W is SPD), stored packed
//! in the order the indices entered. When 𝒜 changes:
//!
//! * an index j that enters is appended: with c = W_𝒜j, solve L z = c, then l = D⁻¹ z and
//!   d = W_jj − zᵀ D⁻¹ z, and [L 0; lᵀ 1] [D 0; 0 d] [Lᵀ l; 0 1] is the factor of the bordered
//!   block (O(k²) for k active indices);
//! * indices that leave are deleted from the factor by faer's
//!   `ldlt::update::delete_rows_and_cols_clobber` (a rank-r update of the trailing block, O(k²)
//!   per index);
//! * when more than a third of the block changes, or after [`MAX_UPDATES`] updates since the last
//!   full factorisation (to bound the accumulation of round-off), it is factored from scratch by
//!   faer's blocked LDLᵀ (O(k³/3)).
//!
//! A full factorisation costs k³/3 flops against about k² per changed index, so a PDAS iteration
//! that moves a few indices costs O(k²) instead of O(k³), and a working set that repeats from one
//! time step to the next (a plate resting on an obstacle) is factored once per step (the factor is
//! not kept from one step to the next, see [`super::delassus`]).

use super::Delassus;
use faer::dyn_stack::{MemStack, StackReq};
use faer::linalg::cholesky::ldlt;
use faer::linalg::triangular_solve::{
    solve_unit_lower_triangular_in_place, solve_unit_upper_triangular_in_place,
};
use faer::{ColMut, Mat, Par};
use std::mem::MaybeUninit;

/// Updates (indices appended or deleted) allowed between two full factorisations.
pub const MAX_UPDATES: usize = 200;

/// The active block is not numerically positive definite (a pivot d ≤ 0 or not finite).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NotPositiveDefinite;

/// How often each kind of factor work ran.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FactorStats {
    /// Full factorisations.
    pub full: usize,
    /// Indices appended by a bordered update.
    pub appended: usize,
    /// Indices deleted by a downdate.
    pub deleted: usize,
    /// Synchronisations within a solve that found the factor already up to date.
    pub reused: usize,
}

/// The LDLᵀ factor of W_𝒜𝒜 for the last working set it was synchronised with (module docs).
#[derive(Clone, Debug)]
pub struct ActiveBlockFactor {
    /// Constrained indices in factor order.
    order: Vec<usize>,
    /// Place of each constrained index in `order`, or `usize::MAX`.
    position: Vec<usize>,
    /// D on the diagonal and L strictly below, in the leading k × k block (k = `order.len()`).
    ld: Mat<f64>,
    /// Updates since the last full factorisation.
    updates: usize,
    stats: FactorStats,
    /// Workspaces.
    column: Vec<f64>,
    marked: Vec<bool>,
    removed: Vec<usize>,
    added: Vec<usize>,
    /// The positions handed to faer's deletion, which overwrites them.
    positions: Vec<usize>,
    /// faer's scratch memory, kept so that a solve on a working set no larger than an earlier
    /// one allocates nothing (scratch is written before it is read: its old contents do not
    /// change a result).
    scratch: Vec<MaybeUninit<u8>>,
}

impl Default for ActiveBlockFactor {
    fn default() -> Self {
        ActiveBlockFactor {
            order: Vec::new(),
            position: Vec::new(),
            ld: Mat::zeros(0, 0),
            updates: 0,
            stats: FactorStats::default(),
            column: Vec::new(),
            marked: Vec::new(),
            removed: Vec::new(),
            added: Vec::new(),
            positions: Vec::new(),
            scratch: Vec::new(),
        }
    }
}

impl ActiveBlockFactor {
    /// An empty factor.
    pub fn new() -> Self {
        Self::default()
    }

    /// Counts of the factor work so far.
    pub fn stats(&self) -> FactorStats {
        self.stats
    }

    /// m, the dimension of the operator it was last [reset](Self::reset) for.
    pub fn dim(&self) -> usize {
        self.position.len()
    }

    /// Forgets the factor and prepares for an operator of dimension `m`: call once at the start
    /// of every solve, before [`Self::sync`].
    pub fn reset(&mut self, m: usize) {
        self.order.clear();
        self.position.clear();
        self.position.resize(m, usize::MAX);
        self.updates = 0;
        self.marked.clear();
        self.marked.resize(m, false);
    }

    /// Brings the factor to W_𝒜𝒜 for `active` (distinct indices < m), by updates or from
    /// scratch (module docs).
    pub fn sync<D: Delassus + ?Sized>(
        &mut self,
        w: &mut D,
        active: &[usize],
    ) -> Result<(), NotPositiveDefinite> {
        for &i in active {
            self.marked[i] = true;
        }
        let mut removed = std::mem::take(&mut self.removed);
        let mut added = std::mem::take(&mut self.added);
        removed.clear();
        removed.extend((0..self.order.len()).filter(|&p| !self.marked[self.order[p]]));
        added.clear();
        added.extend(
            active
                .iter()
                .copied()
                .filter(|&i| self.position[i] == usize::MAX),
        );
        for &i in active {
            self.marked[i] = false;
        }
        let result = self.apply_changes(w, active, &removed, &added);
        self.removed = removed;
        self.added = added;
        result
    }

    /// The work of [`Self::sync`] once the changes are known.
    fn apply_changes<D: Delassus + ?Sized>(
        &mut self,
        w: &mut D,
        active: &[usize],
        removed: &[usize],
        added: &[usize],
    ) -> Result<(), NotPositiveDefinite> {
        let changes = removed.len() + added.len();
        if changes == 0 {
            self.stats.reused += 1;
            return Ok(());
        }
        if 3 * changes > active.len() || self.updates + changes > MAX_UPDATES {
            return self.factor_from_scratch(w, active);
        }
        self.delete(removed);
        w.prefetch(added);
        for &j in added {
            if self.append(w, j).is_err() {
                // Lost positivity to round-off in the update: the full factorisation decides.
                return self.factor_from_scratch(w, active);
            }
        }
        self.updates += changes;
        Ok(())
    }

    /// The indices of the factor, in its order.
    pub fn order(&self) -> &[usize] {
        &self.order
    }

    /// Solves W_𝒜𝒜 x = r in place, with `r` in the factor's [`Self::order`].
    pub fn solve_in_place(&self, r: &mut [f64]) {
        let k = self.order.len();
        if k == 0 {
            return;
        }
        // L z = r, z ← D⁻¹ z, Lᵀ x = z.
        let l = self.ld.as_ref().submatrix(0, 0, k, k);
        solve_unit_lower_triangular_in_place(l, ColMut::from_slice_mut(r).as_mat_mut(), Par::Seq);
        for (p, v) in r.iter_mut().enumerate() {
            *v /= l[(p, p)];
        }
        solve_unit_upper_triangular_in_place(
            l.transpose(),
            ColMut::from_slice_mut(r).as_mat_mut(),
            Par::Seq,
        );
    }

    /// Room for a k × k factor, keeping the leading block.
    fn reserve(&mut self, k: usize) {
        if self.ld.nrows() >= k {
            return;
        }
        let cap = k.max(2 * self.ld.nrows()).max(16);
        let old = self.order.len();
        let mut ld = Mat::zeros(cap, cap);
        ld.as_mut()
            .submatrix_mut(0, 0, old, old)
            .copy_from(self.ld.as_ref().submatrix(0, 0, old, old));
        self.ld = ld;
    }

    fn factor_from_scratch<D: Delassus + ?Sized>(
        &mut self,
        w: &mut D,
        active: &[usize],
    ) -> Result<(), NotPositiveDefinite> {
        for &i in &self.order {
            self.position[i] = usize::MAX;
        }
        self.order.clear();
        let k = active.len();
        self.reserve(k);
        w.prefetch(active);
        for (q, &j) in active.iter().enumerate() {
            let col = w.column(j);
            for (p, &i) in active.iter().enumerate().skip(q) {
                self.ld[(p, q)] = col[i];
            }
        }
        self.stats.full += 1;
        self.updates = 0;
        let stack = scratch(
            &mut self.scratch,
            ldlt::factor::cholesky_in_place_scratch::<f64>(k, Par::Seq, Default::default()),
        );
        let block = self.ld.as_mut().submatrix_mut(0, 0, k, k);
        let result = ldlt::factor::cholesky_in_place(
            block,
            Default::default(),
            Par::Seq,
            stack,
            Default::default(),
        );
        let positive = (0..k).all(|p| {
            let d = self.ld[(p, p)];
            d > 0.0 && d.is_finite()
        });
        if result.is_err() || !positive {
            return Err(NotPositiveDefinite);
        }
        self.order.extend_from_slice(active);
        for (p, &i) in active.iter().enumerate() {
            self.position[i] = p;
        }
        Ok(())
    }

    /// Deletes the indices at the factor positions `removed` (increasing).
    fn delete(&mut self, removed: &[usize]) {
        if removed.is_empty() {
            return;
        }
        let k = self.order.len();
        self.positions.clear();
        self.positions.extend_from_slice(removed);
        let stack = scratch(
            &mut self.scratch,
            ldlt::update::delete_rows_and_cols_clobber_scratch::<f64>(k, removed.len()),
        );
        ldlt::update::delete_rows_and_cols_clobber(
            self.ld.as_mut().submatrix_mut(0, 0, k, k),
            &mut self.positions,
            Par::Seq,
            stack,
        );
        for &p in removed {
            self.position[self.order[p]] = usize::MAX;
        }
        let mut next = removed.iter().peekable();
        let mut p = 0;
        self.order.retain(|_| {
            let keep = next.peek() != Some(&&p);
            if !keep {
                next.next();
            }
            p += 1;
            keep
        });
        for (p, &i) in self.order.iter().enumerate() {
            self.position[i] = p;
        }
        self.stats.deleted += removed.len();
    }

    /// Appends index j (bordered update, module docs).
    fn append<D: Delassus + ?Sized>(
        &mut self,
        w: &mut D,
        j: usize,
    ) -> Result<(), NotPositiveDefinite> {
        let k = self.order.len();
        self.reserve(k + 1);
        let col = w.column(j);
        let w_jj = col[j];
        self.column.clear();
        self.column.extend(self.order.iter().map(|&i| col[i]));
        let l = self.ld.as_ref().submatrix(0, 0, k, k);
        solve_unit_lower_triangular_in_place(
            l,
            ColMut::from_slice_mut(&mut self.column).as_mat_mut(),
            Par::Seq,
        );
        let mut d = w_jj;
        for (p, &z) in self.column.iter().enumerate() {
            let lp = z / self.ld[(p, p)];
            d -= z * lp;
            self.ld[(k, p)] = lp;
        }
        // A pivot that lost all but 1e-13 of W_jj to cancellation is not trusted.
        if !(d > 1e-13 * w_jj && d.is_finite()) {
            return Err(NotPositiveDefinite);
        }
        self.ld[(k, k)] = d;
        self.order.push(j);
        self.position[j] = k;
        self.stats.appended += 1;
        Ok(())
    }
}

/// `buffer` as a stack of at least `req`, grown if it is smaller.
fn scratch(buffer: &mut Vec<MaybeUninit<u8>>, req: StackReq) -> &mut MemStack {
    let bytes = req.unaligned_bytes_required();
    if buffer.len() < bytes {
        buffer.resize(bytes, MaybeUninit::uninit());
    }
    MemStack::new(buffer)
}
