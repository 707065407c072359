//! The Delassus operator W = B A⁻¹ Bᵀ (m × m, symmetric positive definite) of the contact problem,
//! read column by column.
//!
//! Column j of W is B A⁻¹ Bᵀ e_j: one solve with A, restricted to the constrained dofs. A
//! backend with a dense eigenbasis has all of W precomputed ([`DenseDelassus`]); a sparse backend
//! computes columns on demand and keeps them in one [`DelassusCache`], whose memory is bounded by a
//! budget stated in bytes: when the columns it may hold are all in use, the least recently used
//! one is dropped and recomputed if it is needed again.
//!
//! W is constant while A and the constrained dofs are (a whole run), yet the active-set solver
//! factors its active block afresh at every step (a second solve within a step may continue from
//! the first one's factor): a factor kept from earlier steps would make a step's round-off depend
//! on the steps before it, which the stepper's saved state does not hold, and a restored state
//! must continue bit for bit as the run it was taken from.

/// Column access to the Delassus operator W = B A⁻¹ Bᵀ (m × m, symmetric positive definite).
pub trait Delassus {
    /// m, the number of constrained values.
    fn dim(&self) -> usize;
    /// Column j of W, of length m. May compute and cache it on first access; the slice is valid
    /// until the next call.
    fn column(&mut self, j: usize) -> &[f64];
    /// A hint that the columns `columns` are about to be read: an operator that computes columns
    /// may compute them together (one block solve streams the factor of A once for all of them).
    /// The default does nothing.
    fn prefetch(&mut self, columns: &[usize]) {
        let _ = columns;
    }
    /// y += Σ_j λ_j W e_j over j in `columns`, in that order: each y_i receives the additions
    /// λ_j W_ij one after the other, in the order of `columns`. The default reads one column at
    /// a time.
    fn add_columns(&mut self, columns: &[usize], lambda: &[f64], y: &mut [f64]) {
        for &j in columns {
            let l = lambda[j];
            for (yi, ci) in y.iter_mut().zip(self.column(j)) {
                *yi += l * ci;
            }
        }
    }
}

/// A precomputed dense W, column-major.
#[derive(Clone, Debug)]
pub struct DenseDelassus {
    dim: usize,
    values: Vec<f64>,
}

impl DenseDelassus {
    /// W from its m × m entries in column-major order.
    ///
    /// # Panics
    /// If `values.len() != dim * dim`.
    pub fn new(dim: usize, values: Vec<f64>) -> Self {
        assert_eq!(values.len(), dim * dim, "DenseDelassus: need dim² values");
        DenseDelassus { dim, values }
    }

    /// W with entries `entry(i, j)`.
    pub fn from_fn(dim: usize, mut entry: impl FnMut(usize, usize) -> f64) -> Self {
        let mut values = Vec::with_capacity(dim * dim);
        for j in 0..dim {
            for i in 0..dim {
                values.push(entry(i, j));
            }
        }
        DenseDelassus::new(dim, values)
    }

    /// Entry (i, j).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.values[i + j * self.dim]
    }

    /// Column j.
    pub fn col(&self, j: usize) -> &[f64] {
        &self.values[j * self.dim..(j + 1) * self.dim]
    }

    /// [`Delassus::add_columns`] four columns per pass over y: each y_i receives the same
    /// additions in the same order as one pass per column gives it (Rust contracts no a + b·c
    /// into a fused multiply-add), so y is bit-identical, with a quarter of the loads and
    /// stores of y.
    fn add_cols(&self, columns: &[usize], lambda: &[f64], y: &mut [f64]) {
        let mut chunks = columns.chunks_exact(4);
        for chunk in &mut chunks {
            let [a, b, c, d] = [0, 1, 2, 3].map(|k| (lambda[chunk[k]], self.col(chunk[k])));
            let columns = a.1.iter().zip(b.1).zip(c.1.iter().zip(d.1));
            for (yi, ((&wa, &wb), (&wc, &wd))) in y.iter_mut().zip(columns) {
                *yi = *yi + a.0 * wa + b.0 * wb + c.0 * wc + d.0 * wd;
            }
        }
        for &j in chunks.remainder() {
            let l = lambda[j];
            for (yi, ci) in y.iter_mut().zip(self.col(j)) {
                *yi += l * ci;
            }
        }
    }
}

impl Delassus for DenseDelassus {
    fn dim(&self) -> usize {
        self.dim
    }

    fn column(&mut self, j: usize) -> &[f64] {
        self.col(j)
    }

    fn add_columns(&mut self, columns: &[usize], lambda: &[f64], y: &mut [f64]) {
        self.add_cols(columns, lambda, y);
    }
}

/// A shared W read in place (for instance from data several steppers share).
impl Delassus for &DenseDelassus {
    fn dim(&self) -> usize {
        self.dim
    }

    fn column(&mut self, j: usize) -> &[f64] {
        self.col(j)
    }

    fn add_columns(&mut self, columns: &[usize], lambda: &[f64], y: &mut [f64]) {
        self.add_cols(columns, lambda, y);
    }
}

/// Computes columns of W for a [`DelassusCache`]: `columns(js, out)` writes W e_j for each j of
/// `js` into `out` (m × js.len(), column-major), always the same values for the same j. Closures
/// `FnMut(&[usize], &mut [f64])` are column sources.
pub trait ColumnSource {
    /// Writes the columns `js` of W into `out`.
    fn columns(&mut self, js: &[usize], out: &mut [f64]);
}

impl<F: FnMut(&[usize], &mut [f64])> ColumnSource for F {
    fn columns(&mut self, js: &[usize], out: &mut [f64]) {
        self(js, out)
    }
}

/// Default memory budget of a [`DelassusCache`]: 256 MiB, all of W up to m ≈ 5 800 constrained
/// vertices (a 100 × 57 mesh).
pub const DEFAULT_DELASSUS_BUDGET: usize = 256 << 20;

/// Most columns computed by one call of a [`DelassusCache`]'s `compute` (its workspace is
/// m × this many values).
pub const PREFETCH_BLOCK: usize = 32;

/// Mark of a column listed for a prefetch but not yet held.
const PENDING: usize = usize::MAX - 1;

/// What a [`DelassusCache`] did so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheStats {
    /// Columns computed (one solve with A each), recomputations included.
    pub computed: usize,
    /// Calls of `compute` (block solves).
    pub blocks: usize,
    /// Columns dropped to make room.
    pub evicted: usize,
    /// Columns held now.
    pub held: usize,
}

/// W computed column by column on first use and kept within a memory budget: the
/// [`ColumnSource`] computes the columns W e_j = B A⁻¹ Bᵀ e_j (W is the operator of one A for the
/// cache's whole life; make a new cache when A or the constrained dofs change).
/// [`Delassus::prefetch`] computes the missing columns in blocks of [`PREFETCH_BLOCK`] per call.
///
/// At most ⌊budget / (8 m)⌋ columns (at least one) are held; past that the least recently used
/// column is dropped. An active set larger than that still solves, at the price of recomputing
/// columns.
pub struct DelassusCache<F> {
    dim: usize,
    compute: F,
    /// Column storage, `capacity` slots of m values.
    store: Vec<f64>,
    capacity: usize,
    /// Slot of column j, or `usize::MAX`.
    slot_of: Vec<usize>,
    /// Column held in each used slot.
    column_in: Vec<usize>,
    /// Last use of each used slot (a counter, larger is later).
    last_use: Vec<u64>,
    clock: u64,
    stats: CacheStats,
    /// Workspace of [`Delassus::prefetch`].
    batch: Vec<f64>,
    missing: Vec<usize>,
}

impl<F: ColumnSource> DelassusCache<F> {
    /// The column source.
    pub fn source(&self) -> &F {
        &self.compute
    }

    /// The column source (to solve with the same factor of A, for instance).
    pub fn source_mut(&mut self) -> &mut F {
        &mut self.compute
    }

    /// An empty cache for an m × m operator that may hold `budget_bytes` of columns.
    pub fn new(dim: usize, budget_bytes: usize, compute: F) -> Self {
        let column_bytes = 8 * dim.max(1);
        let capacity = (budget_bytes / column_bytes).clamp(1, dim.max(1));
        DelassusCache {
            dim,
            compute,
            store: Vec::new(),
            capacity,
            slot_of: vec![usize::MAX; dim],
            column_in: Vec::new(),
            last_use: Vec::new(),
            clock: 0,
            stats: CacheStats::default(),
            batch: Vec::new(),
            missing: Vec::new(),
        }
    }

    /// A slot for column j (free, or the least recently used one, whose column is dropped),
    /// marked as used now.
    fn claim_slot(&mut self, j: usize) -> usize {
        let slot = if self.column_in.len() < self.capacity {
            self.column_in.push(j);
            self.last_use.push(0);
            self.store.resize(self.column_in.len() * self.dim, 0.0);
            self.column_in.len() - 1
        } else {
            let slot = (0..self.capacity)
                .min_by_key(|&s| self.last_use[s])
                .expect("the capacity is at least one");
            self.slot_of[self.column_in[slot]] = usize::MAX;
            self.column_in[slot] = j;
            self.stats.evicted += 1;
            slot
        };
        self.slot_of[j] = slot;
        self.last_use[slot] = self.clock;
        slot
    }

    /// How many columns may be held at once.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Counts of computed, evicted and held columns.
    pub fn stats(&self) -> CacheStats {
        CacheStats {
            held: self.column_in.len(),
            ..self.stats
        }
    }
}

impl<F: ColumnSource> Delassus for DelassusCache<F> {
    fn dim(&self) -> usize {
        self.dim
    }

    fn column(&mut self, j: usize) -> &[f64] {
        let m = self.dim;
        self.clock += 1;
        let mut slot = self.slot_of[j];
        if slot == usize::MAX {
            slot = self.claim_slot(j);
            self.compute
                .columns(&[j], &mut self.store[slot * m..(slot + 1) * m]);
            self.stats.computed += 1;
            self.stats.blocks += 1;
        }
        self.last_use[slot] = self.clock;
        &self.store[slot * m..(slot + 1) * m]
    }

    fn prefetch(&mut self, columns: &[usize]) {
        let m = self.dim;
        self.clock += 1;
        // The missing columns, no more than the cache holds, in blocks of PREFETCH_BLOCK.
        let mut missing = std::mem::take(&mut self.missing);
        missing.clear();
        for &j in columns {
            if missing.len() == self.capacity {
                break;
            }
            if self.slot_of[j] == usize::MAX {
                self.slot_of[j] = PENDING;
                missing.push(j);
            }
        }
        for block in missing.chunks(PREFETCH_BLOCK) {
            if block.len() < 2 {
                break; // one column costs the same through `column`
            }
            let r = block.len();
            self.batch.resize(m * r, 0.0);
            self.compute.columns(block, &mut self.batch);
            self.stats.computed += r;
            self.stats.blocks += 1;
            for (q, &j) in block.iter().enumerate() {
                let slot = self.claim_slot(j);
                self.store[slot * m..(slot + 1) * m]
                    .copy_from_slice(&self.batch[q * m..(q + 1) * m]);
            }
        }
        for &j in &missing {
            if self.slot_of[j] == PENDING {
                self.slot_of[j] = usize::MAX;
            }
        }
        self.missing = missing;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cache_keeps_the_most_recent_columns_within_its_budget() {
        // W = diag(1, 2, 3, 4) + 0.5 off the diagonal; room for two columns of four values.
        let entry = |i: usize, j: usize| if i == j { 1.0 + i as f64 } else { 0.5 };
        let mut calls = Vec::new();
        let mut cache = DelassusCache::new(4, 2 * 4 * 8, |js: &[usize], out: &mut [f64]| {
            calls.extend_from_slice(js);
            for (q, &j) in js.iter().enumerate() {
                for (i, o) in out[4 * q..4 * (q + 1)].iter_mut().enumerate() {
                    *o = entry(i, j);
                }
            }
        });
        assert_eq!(cache.capacity(), 2);
        assert_eq!(cache.column(0)[0], 1.0);
        assert_eq!(cache.column(1)[1], 2.0);
        assert_eq!(cache.column(0)[1], 0.5); // held: no recomputation
        assert_eq!(cache.column(2)[2], 3.0); // evicts column 1, the least recently used
        assert_eq!(cache.column(0)[0], 1.0);
        assert_eq!(cache.column(1)[3], 0.5); // recomputed, evicts column 2
                                             // A prefetch of two missing columns: one block, both held afterwards.
        cache.prefetch(&[2, 3, 1]);
        assert_eq!(cache.column(3)[3], 4.0);
        assert_eq!(cache.column(2)[0], 0.5);
        let stats = cache.stats();
        assert_eq!(
            stats,
            CacheStats {
                computed: 6,
                blocks: 5,
                evicted: 4,
                held: 2
            }
        );
        drop(cache);
        assert_eq!(calls, [0, 1, 2, 1, 2, 3]);
    }
}
