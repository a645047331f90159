/*
 * Least-squares fit of an ellipsoid (x − c)ᵀ·A·(x − c) = 1 to points, by the linear algebraic
 * fit of the quadric a·x² + b·y² + c·z² + 2d·xy + 2e·xz + 2f·yz + 2g·x + 2h·y + 2i·z = 1, in
 * three models: a full ellipsoid (9 unknowns), one with axes along x, y, z (6), a sphere (4).
 * Points are centred on their mean and scaled before the fit, so µT or m/s² of any size
 * condition alike.
 */
package dev.motionfusion.core.calib

import dev.motionfusion.core.Vector3
import kotlin.math.cbrt
import kotlin.math.sqrt

/** Which ellipsoids a fit may return. */
public enum class EllipsoidModel(internal val unknowns: Int) {
    /** Any ellipsoid: offset and a symmetric matrix (scale and misalignment, or soft iron). */
    FULL(9),

    /** Axes along the device axes: offset and one scale per axis. */
    AXIS_ALIGNED(6),

    /** A sphere: offset only (hard iron). */
    SPHERE(4),
}

/**
 * The fitted ellipsoid: [center] and [unitMatrix], the symmetric positive-definite matrix that
 * maps (x − center) onto the unit sphere.
 */
internal class Ellipsoid(val center: Vector3, val unitMatrix: Matrix3) {
    /** The geometric mean of the semi-axes: the radius of the sphere of equal volume. */
    val meanRadius: Double get() = 1.0 / cbrt(unitMatrix.determinant())

    /** The correction that maps the ellipsoid onto the sphere of [radius]. */
    fun correction(radius: Double) = SensorCorrection(center, unitMatrix * radius)
}

internal object EllipsoidFit {
    /**
     * Fits [model] to the [count] points stored as x, y, z triples in [xyz]. Returns null when
     * the points do not determine it or the quadric is not an ellipsoid.
     */
    fun fit(xyz: DoubleArray, count: Int, model: EllipsoidModel): Ellipsoid? {
        if (count < model.unknowns) return null
        // Centre on the mean (inside the ellipsoid: the quadric form "… = 1" cannot pass through the origin).
        var x0 = 0.0
        var y0 = 0.0
        var z0 = 0.0
        for (i in 0 until count) { x0 += xyz[3 * i]; y0 += xyz[3 * i + 1]; z0 += xyz[3 * i + 2] }
        x0 /= count; y0 /= count; z0 /= count
        var spread = 0.0
        for (i in 0 until count) {
            spread = maxOf(spread, kotlin.math.abs(xyz[3 * i] - x0), kotlin.math.abs(xyz[3 * i + 1] - y0), kotlin.math.abs(xyz[3 * i + 2] - z0))
        }
        if (!(spread > 0.0) || !spread.isFinite()) return null
        val s = 1.0 / spread
        val n = model.unknowns
        val ata = DoubleArray(n * n)
        val atb = DoubleArray(n)
        val row = DoubleArray(n)
        for (i in 0 until count) {
            val x = (xyz[3 * i] - x0) * s
            val y = (xyz[3 * i + 1] - y0) * s
            val z = (xyz[3 * i + 2] - z0) * s
            design(model, x, y, z, row)
            for (r in 0 until n) {
                atb[r] += row[r]
                val rr = row[r]
                for (c in r until n) ata[r * n + c] += rr * row[c]
            }
        }
        for (r in 0 until n) for (c in 0 until r) ata[r * n + c] = ata[c * n + r]
        val p = solveLinear(ata, atb, n) ?: return null
        val a: Matrix3
        val v: Vector3
        when (model) {
            EllipsoidModel.FULL -> { a = Matrix3.symmetric(p[0], p[1], p[2], p[3], p[4], p[5]); v = Vector3(p[6], p[7], p[8]) }
            EllipsoidModel.AXIS_ALIGNED -> { a = Matrix3.diagonal(p[0], p[1], p[2]); v = Vector3(p[3], p[4], p[5]) }
            EllipsoidModel.SPHERE -> { a = Matrix3.diagonal(p[0], p[0], p[0]); v = Vector3(p[1], p[2], p[3]) }
        }
        val c = try { -(a.inverse() * v) } catch (e: IllegalArgumentException) { return null }
        val k = 1.0 + (c dot (a * c))
        if (!(k > 0.0)) return null
        val eig = SymmetricEigen(a * (1.0 / k))
        if (eig.values.any { !(it > 0.0) }) return null
        val unit = eig.map { sqrt(it) } * s
        val center = Vector3(c.x / s + x0, c.y / s + y0, c.z / s + z0)
        return if (center.isFinite() && unit.isFinite()) Ellipsoid(center, unit) else null
    }

    private fun design(model: EllipsoidModel, x: Double, y: Double, z: Double, row: DoubleArray) {
        when (model) {
            EllipsoidModel.FULL -> {
                row[0] = x * x; row[1] = y * y; row[2] = z * z
                row[3] = 2 * x * y; row[4] = 2 * x * z; row[5] = 2 * y * z
                row[6] = 2 * x; row[7] = 2 * y; row[8] = 2 * z
            }
            EllipsoidModel.AXIS_ALIGNED -> {
                row[0] = x * x; row[1] = y * y; row[2] = z * z
                row[3] = 2 * x; row[4] = 2 * y; row[5] = 2 * z
            }
            EllipsoidModel.SPHERE -> {
                row[0] = x * x + y * y + z * z
                row[1] = 2 * x; row[2] = 2 * y; row[3] = 2 * z
            }
        }
    }
}

/**
 * Coverage of the sphere of directions on an equal-area grid: [BANDS] bands of equal height in
 * z (equal area by Archimedes' hat-box theorem) times [SECTORS] sectors of longitude, so every
 * cell is 4π / [CELLS] sr (about 18° × 18° at the equator). Drawn with z up and longitude
 * across, the cells are the equal rectangles of Lambert's cylindrical equal-area map. Cell
 * `band * SECTORS + sector`: band 0 holds z/|v| in [−1, −1 + 2/BANDS), sector 0 longitudes
 * atan2(y, x) in [−π, −π + 2π/SECTORS).
 */
public class DirectionCoverage {
    private val hits = IntArray(CELLS)

    /** Counts the direction of (x, y, z); a zero or non-finite vector is ignored. */
    public fun add(x: Double, y: Double, z: Double) {
        val c = cellOf(x, y, z)
        if (c >= 0) hits[c]++
    }

    /** Directions counted in [cell] (0 until [CELLS]). */
    public fun hits(cell: Int): Int = hits[cell]

    /** Cells holding at least one direction. */
    public val covered: Int get() = hits.count { it > 0 }

    /** Fraction of cells holding at least one direction, 0 … 1. */
    public val fraction: Double get() = covered.toDouble() / CELLS

    public companion object {
        public const val BANDS: Int = 8
        public const val SECTORS: Int = 16
        public const val CELLS: Int = BANDS * SECTORS

        /** The cell of the direction of (x, y, z), or −1 for a zero or non-finite vector. */
        @JvmStatic
        public fun cellOf(x: Double, y: Double, z: Double): Int {
            val n = sqrt(x * x + y * y + z * z)
            if (!(n > 0.0) || !n.isFinite()) return -1
            val band = (((z / n) + 1.0) * 0.5 * BANDS).toInt().coerceIn(0, BANDS - 1)
            val lon = kotlin.math.atan2(y, x) // −π … π
            val sector = ((lon + Math.PI) / (2 * Math.PI) * SECTORS).toInt().coerceIn(0, SECTORS - 1)
            return band * SECTORS + sector
        }
    }
}
