//! The cell grid a rebuild bins the particles into.

use super::*;

/// The cells of [`NeighbourList::bin_cells`].
#[derive(Debug, Clone, Copy)]
pub(super) struct Grid {
    pub(super) ymin: f64,
    pub(super) cutoff: f64,
    pub(super) rows: usize,
    pub(super) columns: usize,
    pub(super) column_width: f64,
}

impl Grid {
    /// The (row, column) of a particle at (x, y), x in [0, width) (a
    /// position outside, or NaN, is put in the nearest cell).
    #[inline]
    pub(super) fn cell(&self, x: f64, y: f64) -> (usize, usize) {
        let row = (((y - self.ymin) / self.cutoff) as usize).min(self.rows - 1);
        let column = ((x / self.column_width) as usize).min(self.columns - 1);
        (row, column)
    }

    /// The columns within one of column `c`, periodic: all (one) of a
    /// narrow strip, else `c - 1`, `c`, `c + 1` (three distinct columns).
    #[inline]
    pub(super) fn columns_near(&self, c: usize) -> impl Iterator<Item = usize> {
        let n = self.columns;
        let (first, count) = if n == 1 { (0, 1) } else { (c + n - 1, 3) };
        (0..count).map(move |k| (first + k) % n)
    }

    /// The cells of [`Self::columns_near`] in row `row`, as runs of
    /// consecutive cells `a..b`: one, or two where they wrap at the
    /// strip's edge (the second empty otherwise).
    #[inline]
    pub(super) fn runs_near(&self, row: usize, c: usize) -> [(usize, usize); 2] {
        let (n, first) = (self.columns, row * self.columns);
        if n < 3 {
            [(first, first + n), (first, first)]
        } else if c == 0 {
            [(first + n - 1, first + n), (first, first + 2)]
        } else if c == n - 1 {
            [(first + n - 2, first + n), (first, first + 1)]
        } else {
            [(first + c - 1, first + c + 2), (first, first)]
        }
    }
}

impl NeighbourList {
    /// Counting sort of the particles into cells: rows of height `cutoff`
    /// in y from the lowest particle and, when the strip is at least three
    /// cutoffs wide, columns at least `cutoff` wide in x (periodic);
    /// otherwise one column (a narrow strip: every image of every particle
    /// in the rows near is tested). Within a cell, particles by index; their
    /// positions beside them (`bin_x`, `bin_y`).
    pub(super) fn bin_cells(&mut self, x: &[f64], y: &[f64], width: f64, cutoff: f64) -> Grid {
        let ymin = y.iter().copied().fold(f64::INFINITY, f64::min);
        let ymax = y.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        // Rows of height `cutoff` from the lowest particle; no more rows than
        // particles (the last one takes the rest), and one for a span that is
        // not finite (a blown-up state, about to be reported).
        let span = ymax - ymin;
        let rows = if span.is_finite() {
            (span / cutoff).floor().min(y.len() as f64) as usize + 1
        } else {
            1
        };
        let fit = (width / cutoff).floor();
        let columns = if fit >= 3.0 {
            (fit as usize).min(y.len())
        } else {
            1
        };
        let grid = Grid {
            ymin,
            cutoff,
            rows,
            columns,
            column_width: width / columns as f64,
        };
        let cells = rows * columns;
        self.bin_start.clear();
        self.bin_start.resize(cells + 1, 0);
        let cell_of = |i: usize| {
            let (r, c) = grid.cell(x[i], y[i]);
            r * columns + c
        };
        for i in 0..y.len() {
            self.bin_start[cell_of(i) + 1] += 1;
        }
        for b in 0..cells {
            self.bin_start[b + 1] += self.bin_start[b];
        }
        self.bin_items.resize(y.len(), 0);
        self.bin_x.resize(y.len(), 0.0);
        self.bin_y.resize(y.len(), 0.0);
        let mut fill = self.bin_start.clone();
        for i in 0..y.len() {
            let b = cell_of(i);
            let at = fill[b] as usize;
            self.bin_items[at] = i as u32;
            (self.bin_x[at], self.bin_y[at]) = (x[i], y[i]);
            fill[b] += 1;
        }
        grid
    }
}
