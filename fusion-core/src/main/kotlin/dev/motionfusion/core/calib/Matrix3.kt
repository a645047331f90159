/*
 * A 3×3 matrix for sensor calibration (soft iron, scale and misalignment): immutable, row-major
 * (m_RC = row R, column C), as the rotation matrices of docs/CONVENTIONS.md.
 */
package dev.motionfusion.core.calib

import dev.motionfusion.core.Vector3
import kotlin.math.abs
import kotlin.math.sqrt

/** An immutable 3×3 matrix; [values] are row-major. */
public class Matrix3 private constructor(private val m: DoubleArray) {

    /** Element at [row], [column] (0-based). */
    public operator fun get(row: Int, column: Int): Double = m[3 * row + column]

    /** The nine elements, row-major (a copy). */
    public val values: DoubleArray get() = m.copyOf()

    public operator fun times(v: Vector3): Vector3 = Vector3(
        m[0] * v.x + m[1] * v.y + m[2] * v.z,
        m[3] * v.x + m[4] * v.y + m[5] * v.z,
        m[6] * v.x + m[7] * v.y + m[8] * v.z,
    )

    public operator fun times(o: Matrix3): Matrix3 = Matrix3(DoubleArray(9) { i ->
        val r = i / 3
        val c = i % 3
        m[3 * r] * o.m[c] + m[3 * r + 1] * o.m[3 + c] + m[3 * r + 2] * o.m[6 + c]
    })

    public operator fun plus(o: Matrix3): Matrix3 = Matrix3(DoubleArray(9) { m[it] + o.m[it] })

    public operator fun times(s: Double): Matrix3 = Matrix3(DoubleArray(9) { m[it] * s })

    public fun transpose(): Matrix3 = Matrix3(DoubleArray(9) { i -> m[3 * (i % 3) + i / 3] })

    public fun determinant(): Double =
        m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6])

    /** The inverse; throws IllegalArgumentException when singular. */
    public fun inverse(): Matrix3 {
        val d = determinant()
        require(d != 0.0 && d.isFinite()) { "singular matrix" }
        val c = doubleArrayOf(
            m[4] * m[8] - m[5] * m[7], m[2] * m[7] - m[1] * m[8], m[1] * m[5] - m[2] * m[4],
            m[5] * m[6] - m[3] * m[8], m[0] * m[8] - m[2] * m[6], m[2] * m[3] - m[0] * m[5],
            m[3] * m[7] - m[4] * m[6], m[1] * m[6] - m[0] * m[7], m[0] * m[4] - m[1] * m[3],
        )
        return Matrix3(DoubleArray(9) { c[it] / d })
    }

    public fun isFinite(): Boolean = m.all { it.isFinite() }

    /** True when the matrix equals its transpose within [tolerance]. */
    public fun isSymmetric(tolerance: Double = 1e-12): Boolean =
        abs(m[1] - m[3]) <= tolerance && abs(m[2] - m[6]) <= tolerance && abs(m[5] - m[7]) <= tolerance

    /** Largest absolute element difference to [o]. */
    public fun maxDifference(o: Matrix3): Double = (0 until 9).maxOf { abs(m[it] - o.m[it]) }

    override fun equals(other: Any?): Boolean = other is Matrix3 && m.contentEquals(other.m)
    override fun hashCode(): Int = m.contentHashCode()
    override fun toString(): String = "Matrix3(${m.joinToString(", ")})"

    internal fun copyInto(out: DoubleArray) = m.copyInto(out)

    public companion object {
        @JvmField
        public val IDENTITY: Matrix3 = diagonal(1.0, 1.0, 1.0)

        /** From nine row-major elements. */
        @JvmStatic
        public fun of(vararg rowMajor: Double): Matrix3 {
            require(rowMajor.size == 9) { "a 3×3 matrix needs 9 elements, got ${rowMajor.size}" }
            return Matrix3(rowMajor.copyOf())
        }

        @JvmStatic
        public fun diagonal(x: Double, y: Double, z: Double): Matrix3 = Matrix3(doubleArrayOf(x, 0.0, 0.0, 0.0, y, 0.0, 0.0, 0.0, z))

        /** The symmetric matrix with diagonal [d] and off-diagonal elements xy, xz, yz. */
        @JvmStatic
        public fun symmetric(xx: Double, yy: Double, zz: Double, xy: Double, xz: Double, yz: Double): Matrix3 =
            Matrix3(doubleArrayOf(xx, xy, xz, xy, yy, yz, xz, yz, zz))
    }
}

/** Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations: A = V·diag(λ)·Vᵀ. */
internal class SymmetricEigen(a: Matrix3) {
    /** Eigenvalues (unsorted). */
    val values = DoubleArray(3)

    /** Eigenvectors as the columns of a row-major 3×3 array. */
    val vectors = DoubleArray(9)

    init {
        val s = a.values
        // Symmetrise against rounding.
        s[1] = 0.5 * (s[1] + s[3]); s[3] = s[1]
        s[2] = 0.5 * (s[2] + s[6]); s[6] = s[2]
        s[5] = 0.5 * (s[5] + s[7]); s[7] = s[5]
        val v = doubleArrayOf(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
        for (sweep in 0 until 50) {
            val off = s[1] * s[1] + s[2] * s[2] + s[5] * s[5]
            if (off <= 1e-30 * (s[0] * s[0] + s[4] * s[4] + s[8] * s[8]) || off == 0.0) break
            for ((p, q) in PAIRS) {
                val apq = s[3 * p + q]
                if (apq == 0.0) continue
                val theta = (s[3 * q + q] - s[3 * p + p]) / (2.0 * apq)
                val t = (if (theta >= 0) 1.0 else -1.0) / (abs(theta) + sqrt(theta * theta + 1.0))
                val c = 1.0 / sqrt(t * t + 1.0)
                val sn = t * c
                // A' = Jᵀ A J with J the rotation in the (p, q) plane.
                for (k in 0 until 3) {
                    val akp = s[3 * k + p]
                    val akq = s[3 * k + q]
                    s[3 * k + p] = c * akp - sn * akq
                    s[3 * k + q] = sn * akp + c * akq
                }
                for (k in 0 until 3) {
                    val apk = s[3 * p + k]
                    val aqk = s[3 * q + k]
                    s[3 * p + k] = c * apk - sn * aqk
                    s[3 * q + k] = sn * apk + c * aqk
                }
                for (k in 0 until 3) {
                    val vkp = v[3 * k + p]
                    val vkq = v[3 * k + q]
                    v[3 * k + p] = c * vkp - sn * vkq
                    v[3 * k + q] = sn * vkp + c * vkq
                }
            }
        }
        values[0] = s[0]; values[1] = s[4]; values[2] = s[8]
        v.copyInto(vectors)
    }

    /** V·diag(f(λ))·Vᵀ. */
    fun map(f: (Double) -> Double): Matrix3 {
        val fl = DoubleArray(3) { f(values[it]) }
        return Matrix3.of(*DoubleArray(9) { i ->
            val r = i / 3
            val c = i % 3
            (0 until 3).sumOf { k -> vectors[3 * r + k] * fl[k] * vectors[3 * c + k] }
        })
    }

    private companion object {
        val PAIRS = listOf(0 to 1, 0 to 2, 1 to 2)
    }
}

/** Solves the n×n system [a]·x = [b] (row-major, both overwritten) by Gaussian elimination with partial pivoting; null when singular. */
internal fun solveLinear(a: DoubleArray, b: DoubleArray, n: Int): DoubleArray? {
    var scale = 0.0
    for (v in a) scale = maxOf(scale, abs(v))
    if (!(scale > 0.0)) return null
    for (col in 0 until n) {
        var piv = col
        for (r in col + 1 until n) if (abs(a[r * n + col]) > abs(a[piv * n + col])) piv = r
        if (abs(a[piv * n + col]) <= 1e-13 * scale) return null
        if (piv != col) {
            for (k in 0 until n) { val t = a[col * n + k]; a[col * n + k] = a[piv * n + k]; a[piv * n + k] = t }
            val t = b[col]; b[col] = b[piv]; b[piv] = t
        }
        for (r in col + 1 until n) {
            val f = a[r * n + col] / a[col * n + col]
            if (f == 0.0) continue
            for (k in col until n) a[r * n + k] -= f * a[col * n + k]
            b[r] -= f * b[col]
        }
    }
    val x = DoubleArray(n)
    for (r in n - 1 downTo 0) {
        var s = b[r]
        for (k in r + 1 until n) s -= a[r * n + k] * x[k]
        x[r] = s / a[r * n + r]
    }
    return x
}
