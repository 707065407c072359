//! A fill-reducing ordering for the sparse Cholesky factor of a plate's A: nested dissection by
//! the grid lines of a structured mesh.
//!
//! Each unknown sits at a node of the mesh (a vertex, or an edge midpoint for Argyris), given in
//! half-cell units: the node at (x, y) of a mesh with cells of size hx × hy has the lattice point
//! (round(2x/hx), round(2y/hy)), so vertices have even coordinates and the grid lines that
//! separate columns (rows) of cells are the even values of x (y). A cell touches only the nodes
//! within its closed rectangle, so the unknowns on one grid line separate those on either side of
//! it: no entry of A couples the two sides. Nested dissection orders the two sides first, each by
//! the same rule recursively, and the separating line last; the Cholesky factor of A then fills
//! in only within the blocks of the recursion, as for a mesh of n unknowns it has O(n log n)
//! entries, against the O(n^1.5) of a band ordering.
//!
//! For the Argyris 60 × 30 plate (16 651 free dofs) the factor has 2.38 M entries with this
//! ordering against 2.69 M with faer's approximate minimum degree (AMD), and a solve takes about
//! a quarter less time; for FVS the two are within 1 %. [`super::cholesky::CholeskyAnalysis`]
//! analyses both and keeps the ordering whose factor is smaller, so a mesh where the lines do not
//! separate (not a structured one) costs nothing but the comparison.

/// Leaves of the recursion with at most this many unknowns keep their given order: below this
/// size the fill hardly depends on the order (measured on Argyris 60 × 30: 2.35 M entries with
/// leaves of 1 unknown, 2.38 M with 12, 2.44 M with 32), and larger leaves make larger supernodes.
pub const LEAF_SIZE: usize = 12;

/// The nested-dissection order of the unknowns at the lattice points `points` (module docs):
/// `order[p]` is the unknown placed at position p. Each region is split by the even line closest
/// to the middle of its longer side, strictly inside its bounding box; a region with no such line,
/// or with at most [`LEAF_SIZE`] unknowns, is a leaf.
pub fn nested_dissection(points: &[[i64; 2]]) -> Vec<usize> {
    let mut order = Vec::with_capacity(points.len());
    dissect(points, (0..points.len()).collect(), &mut order);
    order
}

/// Appends the order of the unknowns `region` to `order`.
fn dissect(points: &[[i64; 2]], region: Vec<usize>, order: &mut Vec<usize>) {
    let Some((axis, line)) = split_line(points, &region) else {
        order.extend(region);
        return;
    };
    let (mut below, mut above, mut separator) = (Vec::new(), Vec::new(), Vec::new());
    for i in region {
        match points[i][axis].cmp(&line) {
            std::cmp::Ordering::Less => below.push(i),
            std::cmp::Ordering::Greater => above.push(i),
            std::cmp::Ordering::Equal => separator.push(i),
        }
    }
    dissect(points, below, order);
    dissect(points, above, order);
    order.extend(separator);
}

/// The axis and the even coordinate of the line that splits `region`, if it is to be split: both
/// sides then hold the points at the ends of the bounding box, so the recursion ends.
fn split_line(points: &[[i64; 2]], region: &[usize]) -> Option<(usize, i64)> {
    if region.len() <= LEAF_SIZE {
        return None;
    }
    let (mut low, mut high) = ([i64::MAX; 2], [i64::MIN; 2]);
    for &i in region {
        for axis in 0..2 {
            low[axis] = low[axis].min(points[i][axis]);
            high[axis] = high[axis].max(points[i][axis]);
        }
    }
    let axis = usize::from(high[1] - low[1] > high[0] - low[0]);
    let (low, high) = (low[axis], high[axis]);
    // The even value at or below the middle, moved up if it is not strictly inside.
    let mut line = (low + high).div_euclid(2);
    line -= line.rem_euclid(2);
    if line <= low {
        line += 2;
    }
    (line < high).then_some((axis, line))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vertices of an nx × ny grid of cells, in half-cell units, row by row.
    fn grid(nx: i64, ny: i64) -> Vec<[i64; 2]> {
        (0..=ny)
            .flat_map(|j| (0..=nx).map(move |i| [2 * i, 2 * j]))
            .collect()
    }

    #[test]
    fn the_order_is_a_permutation_with_the_separator_last() {
        let points = grid(8, 4);
        let order = nested_dissection(&points);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..points.len()).collect::<Vec<_>>());
        // The first split of the 8 × 4 grid is the vertical line x = 4 cells (8 half-cells): its
        // five vertices come last, and every vertex left of it before every vertex right of it.
        let tail: Vec<[i64; 2]> = order[order.len() - 5..]
            .iter()
            .map(|&i| points[i])
            .collect();
        assert!(tail.iter().all(|p| p[0] == 8), "{tail:?}");
        let position = |x: i64| {
            order
                .iter()
                .position(|&i| points[i][0] == x)
                .expect("a vertex on that line")
        };
        let last_left = order
            .iter()
            .rposition(|&i| points[i][0] < 8)
            .expect("a vertex left of the separator");
        assert!(last_left < position(10), "left side first, then the right");
    }

    #[test]
    fn regions_without_a_line_inside_are_leaves() {
        // A single column of 20 vertices, one cell wide: split along y only; the points of one
        // vertical line never cause an empty side.
        let points: Vec<[i64; 2]> = (0..20).map(|j| [0, 2 * j]).collect();
        let order = nested_dissection(&points);
        assert_eq!(order.len(), 20);
        // The nodes of one cell (corners, edge midpoints, centre) repeated past the leaf size: no
        // even line lies strictly inside the box [0, 2]², so it stays a leaf in its given order.
        let points: Vec<[i64; 2]> = (0..40).map(|k| [k % 3, (k / 3) % 3]).collect();
        assert_eq!(nested_dissection(&points), (0..40).collect::<Vec<_>>());
    }
}
