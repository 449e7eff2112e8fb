//! A short list kept on the stack: the polygon kernels' working lists (vertices, clipped
//! polygons, crossings), which for a rectangle or a polygon of a few sides hold a handful of
//! points. Up to `N` items live in a fixed array; a longer list moves to the heap once, so a
//! contact of small polygons (a rectangle's, every step) allocates nothing.

/// A list of up to `N` items on the stack, and of any length on the heap beyond.
#[derive(Clone, Debug)]
pub(crate) struct Small<T: Copy, const N: usize> {
    inline: [T; N],
    len: usize,
    /// All the items once there are more than `N` (empty until then).
    heap: Vec<T>,
}

/// The size the polygon kernels' lists are kept on the stack up to: a rectangle's lists (four
/// corners, a clipped polygon of up to eight) and those of polygons of up to about a dozen
/// sides.
pub(crate) const ON_STACK: usize = 16;

/// A polygon kernel's working list.
pub(crate) type List<T> = Small<T, ON_STACK>;

impl<T: Copy + Default, const N: usize> Small<T, N> {
    /// An empty list.
    #[inline]
    pub fn new() -> Self {
        Small {
            inline: [T::default(); N],
            len: 0,
            heap: Vec::new(),
        }
    }

    /// Appends `x`.
    #[inline]
    pub fn push(&mut self, x: T) {
        if self.len < N {
            self.inline[self.len] = x;
        } else {
            if self.len == N {
                self.heap.clear();
                self.heap.extend_from_slice(&self.inline);
            }
            self.heap.push(x);
        }
        self.len += 1;
    }

    /// Empties the list (keeping any heap block for reuse).
    #[inline]
    pub fn clear(&mut self) {
        self.len = 0;
    }
}

impl<T: Copy, const N: usize> std::ops::Deref for Small<T, N> {
    type Target = [T];
    #[inline]
    fn deref(&self) -> &[T] {
        if self.len <= N {
            &self.inline[..self.len]
        } else {
            &self.heap
        }
    }
}

impl<T: Copy, const N: usize> std::ops::DerefMut for Small<T, N> {
    #[inline]
    fn deref_mut(&mut self) -> &mut [T] {
        if self.len <= N {
            &mut self.inline[..self.len]
        } else {
            &mut self.heap
        }
    }
}

impl<T: Copy + Default, const N: usize> FromIterator<T> for Small<T, N> {
    #[inline]
    fn from_iter<I: IntoIterator<Item = T>>(iter: I) -> Self {
        let mut s = Small::new();
        for x in iter {
            s.push(x);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_its_items_in_order_on_the_stack_and_beyond() {
        let mut s: Small<usize, 4> = Small::new();
        for k in 0..4 {
            s.push(k);
        }
        assert!(s.heap.is_empty());
        assert_eq!(&s[..], &[0, 1, 2, 3]);
        for k in 4..9 {
            s.push(k);
        }
        assert_eq!(&s[..], &(0..9).collect::<Vec<_>>()[..]);
        s[8] = 80;
        assert_eq!(s[8], 80);
        s.clear();
        assert!(s.is_empty());
        for k in 0..6 {
            s.push(10 + k);
        }
        assert_eq!(&s[..], &[10, 11, 12, 13, 14, 15]);
        let t: Small<usize, 2> = (0..3).collect();
        assert_eq!(&t[..], &[0, 1, 2]);
    }
}
