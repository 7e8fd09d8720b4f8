//! The lower triangle of a symmetric matrix in compressed columns with 4-byte
//! row indices: what the numeric factorization ([`super::factor`]) reads and
//! the Cholesky facade ([`super::linear`]) hands it. Its own module, below both,
//! so that neither imports the other for it.

use std::borrow::Cow;

/// The lower triangle of a symmetric matrix in compressed columns, with row
/// indices of 4 bytes (as [`crate::assembly::Stiffness`] stores them): what
/// [`super::linear::CholeskySolver::factorize`] reads, without a widened copy of the indices.
/// Its values are borrowed ([`LowerMatrix::new`]) or given to the factorization
/// ([`LowerMatrix::with_values`]), which then gives their pages back as it
/// reads them.
#[derive(Debug, Clone)]
pub struct LowerMatrix<'a> {
    col_ptr: &'a [usize],
    row_idx: &'a [u32],
    values: Cow<'a, [f64]>,
}

impl<'a> LowerMatrix<'a> {
    /// The matrix of `n = col_ptr.len() − 1` columns whose column `j` has the rows
    /// `row_idx[col_ptr[j]..col_ptr[j + 1]]` (each ≥ j) and their `values`.
    ///
    /// # Panics
    /// If the arrays do not describe such a matrix (pointers not ascending from 0
    /// to the number of rows stored, values and rows of different lengths). A row
    /// out of range panics where the factorization meets it.
    pub fn new(col_ptr: &'a [usize], row_idx: &'a [u32], values: &'a [f64]) -> Self {
        Self::checked(col_ptr, row_idx, Cow::Borrowed(values))
    }

    /// [`LowerMatrix::new`] with the values given by value: a factorization with
    /// its tree split loads the top supernodes from them first, then each
    /// subtree's thread gives back the pages of the values it has read as it
    /// goes, so they shrink while the factor grows instead of sitting beside the
    /// whole factor (see [`super::factor::NumericPlan::factorize`]).
    pub fn with_values(col_ptr: &'a [usize], row_idx: &'a [u32], values: Vec<f64>) -> Self {
        Self::checked(col_ptr, row_idx, Cow::Owned(values))
    }

    fn checked(col_ptr: &'a [usize], row_idx: &'a [u32], values: Cow<'a, [f64]>) -> Self {
        let n = col_ptr.len().saturating_sub(1);
        assert!(
            col_ptr.first() == Some(&0)
                && col_ptr.windows(2).all(|w| w[0] <= w[1])
                && col_ptr[n] == row_idx.len()
                && values.len() == row_idx.len(),
            "not a compressed-column matrix"
        );
        LowerMatrix {
            col_ptr,
            row_idx,
            values,
        }
    }

    /// Number of rows and columns.
    pub fn n(&self) -> usize {
        self.col_ptr.len() - 1
    }

    /// The column pointers, the rows and the values, taken apart.
    pub(crate) fn into_parts(self) -> (&'a [usize], &'a [u32], Cow<'a, [f64]>) {
        (self.col_ptr, self.row_idx, self.values)
    }
}
