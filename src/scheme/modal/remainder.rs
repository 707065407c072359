//! A bound on the part of a vertex's value past a number of modes, blockwise: with the modes from
//! d on split into blocks B_1, B_2, … at fixed boundaries,
//!
//!   |Σ_{k ≥ d} C_ik q_k| ≤ Σ_b ‖C_{i,B_b}‖ ‖q_{B_b}‖ ≤ ‖C_{i,k≥d}‖ ‖q_{k≥d}‖
//!
//! (Cauchy–Schwarz within each block, then over the vector of block norms). The first bound is
//! the tighter wherever the weight of q and that of row i lie in different blocks: q's in the low
//! modes, a plate's rows spread over all of them. On Argyris 28 × 20 (5 257 modes) dyadic blocks
//! from mode 32 on take the stand-ins' bounds below the single Cauchy–Schwarz product by enough
//! that a step with a QP sums a third fewer vertices over 128 modes and reads 16 % fewer full
//! rows (`cargo bench --bench solver -- --case sweep-argyris-28x20-modal`, docs/speed.md).

use crate::scheme::vectors::sum_of_squares;
use faer::Mat;

/// The block boundaries and the norms ‖C_{i,B_b}‖ of every row's blocks (module docs).
#[derive(Clone, Debug)]
pub(super) struct BlockRemainder {
    /// The boundaries d_0 < d_1 < … < d_r = n: block b holds the modes d_b..d_{b+1}.
    starts: Vec<usize>,
    /// ‖C_{i,B_b}‖₂, row-major: vertex i's r block norms are contiguous.
    row_blocks: Vec<f64>,
}

impl BlockRemainder {
    /// The blocks of the rows of `c` (m × n) from mode `from` on: boundaries at `from` and its
    /// doublings, and at every mode count of `depths` past `from`, cut at n.
    pub(super) fn new(c: &Mat<f64>, from: usize, depths: &[usize]) -> BlockRemainder {
        let (m, n) = (c.nrows(), c.ncols());
        let mut starts: Vec<usize> = std::iter::successors(Some(from), |&d| Some(2 * d))
            .take_while(|&d| d < n)
            .chain(depths.iter().copied().filter(|&d| d > from && d < n))
            .collect();
        starts.sort_unstable();
        starts.dedup();
        starts.push(n);
        let r = starts.len() - 1;
        let mut row_blocks = Vec::with_capacity(m * r);
        for i in 0..m {
            row_blocks.extend(
                starts
                    .windows(2)
                    .map(|b| c.row(i).subcols(b[0], b[1] - b[0]).norm_l2()),
            );
        }
        BlockRemainder { starts, row_blocks }
    }

    /// The number of blocks.
    pub(super) fn blocks(&self) -> usize {
        self.starts.len() - 1
    }

    /// ‖q_{B_b}‖ of every block, into `out` (resized to the number of blocks).
    pub(super) fn block_norms(&self, q: &[f64], out: &mut Vec<f64>) {
        out.clear();
        out.extend(
            self.starts
                .windows(2)
                .map(|b| sum_of_squares(&q[b[0]..b[1]]).sqrt()),
        );
    }

    /// The bound on |Σ_{k ≥ depth} C_ik q_k| from the block norms `q_blocks` of q
    /// ([`Self::block_norms`]); `depth` must be a boundary (0 past n: n itself).
    pub(super) fn bound(&self, i: usize, depth: usize, q_blocks: &[f64]) -> f64 {
        let r = self.blocks();
        let first = self
            .starts
            .binary_search(&depth)
            .expect("a remainder bound starts at a block boundary");
        self.row_blocks[i * r + first.min(r)..(i + 1) * r]
            .iter()
            .zip(&q_blocks[first.min(r)..])
            .map(|(a, s)| a * s)
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The blockwise bound holds, and is no looser than the single Cauchy–Schwarz product, for
    /// every vertex and depth of a random-looking row set.
    #[test]
    fn the_block_bound_holds_and_is_no_looser_than_one_product() {
        let (m, n) = (7, 300);
        let c = Mat::from_fn(m, n, |i, k| ((i * 37 + k * 11) % 29) as f64 / 29.0 - 0.5);
        let remainder = BlockRemainder::new(&c, 32, &[100, 250]);
        assert_eq!(remainder.starts, [32, 64, 100, 128, 250, 256, n]);
        let mut blocks = Vec::new();
        for case in 0..50 {
            let q: Vec<f64> = (0..n)
                .map(|k| ((case * 7 + k * 3) as f64).sin() / (1.0 + k as f64).powf(0.5))
                .collect();
            remainder.block_norms(&q, &mut blocks);
            for i in 0..m {
                for &depth in &remainder.starts {
                    let bound = remainder.bound(i, depth, &blocks);
                    let exact: f64 = (depth..n).map(|k| c[(i, k)] * q[k]).sum();
                    let single = c.row(i).subcols(depth, n - depth).norm_l2()
                        * sum_of_squares(&q[depth..]).sqrt();
                    assert!(exact.abs() <= bound * (1.0 + 1e-12), "{case} {i} {depth}");
                    assert!(bound <= single * (1.0 + 1e-12), "{case} {i} {depth}");
                }
            }
        }
    }
}
