//! Values kept per body component by component (a structure of arrays, `[[T; B]; K]`):
//! the layout in which a loop whose bodies are independent of each other runs over
//! several bodies at once in vector registers. [`Columns`] is such an array written
//! body by body before it is read whole, and not zeroed first. (Crate-private: the
//! compact kernels' working layout, not an interface.)

use std::mem::MaybeUninit;

/// Body `i`'s `K` values in a whole array of columns.
#[inline(always)]
pub fn body<T: Copy, const B: usize, const K: usize>(a: &[[T; B]; K], i: usize) -> [T; K] {
    std::array::from_fn(|k| a[k][i])
}

/// `K` values per body, component by component, each body's written (at least once)
/// before the whole is read.
pub struct Columns<T, const B: usize, const K: usize>([[MaybeUninit<T>; B]; K]);

impl<T: Copy, const B: usize, const K: usize> Columns<T, B, K> {
    #[inline(always)]
    pub fn new() -> Self {
        Columns([const { [const { MaybeUninit::uninit() }; B] }; K])
    }

    /// Writes body `i`'s values.
    ///
    /// # Panics
    /// If `i >= B` (before anything is written).
    #[inline(always)]
    pub fn set(&mut self, i: usize, x: [T; K]) {
        for (c, x) in self.0.iter_mut().zip(x) {
            c[i].write(x);
        }
    }

    /// Body `i`'s values.
    ///
    /// # Safety
    /// [`set`](Self::set) has written them.
    #[inline(always)]
    pub unsafe fn read(&self, i: usize) -> [T; K] {
        // SAFETY: the caller's promise.
        std::array::from_fn(|k| unsafe { self.0[k][i].assume_init() })
    }

    /// The whole array.
    ///
    /// # Safety
    /// [`set`](Self::set) has written every body's values.
    #[inline(always)]
    pub unsafe fn whole(&self) -> &[[T; B]; K] {
        // SAFETY: every entry is written (the caller's promise), and `MaybeUninit<T>`
        // has `T`'s layout, arrays of them alike.
        unsafe { &*(&raw const self.0).cast::<[[T; B]; K]>() }
    }

    /// [`whole`](Self::whole), to change.
    ///
    /// # Safety
    /// As for [`whole`](Self::whole).
    #[inline(always)]
    pub unsafe fn whole_mut(&mut self) -> &mut [[T; B]; K] {
        // SAFETY: as in `whole`.
        unsafe { &mut *(&raw mut self.0).cast::<[[T; B]; K]>() }
    }
}
