/*
 * Vector3: an immutable 3-vector in double precision.
 *
 * Frames and units are those of the values it holds; the project's conventions
 * (docs/CONVENTIONS.md) say which: sensor readings are in the Android device frame
 * (x right, y up along the screen, z out of the screen), in SI units
 * (rad/s, m/s², µT).
 */
package dev.motionfusion.core

import kotlin.math.sqrt

/** An immutable vector of three doubles. */
public data class Vector3(val x: Double, val y: Double, val z: Double) {

    /** Componentwise sum (both in the same frame). */
    public operator fun plus(o: Vector3): Vector3 = Vector3(x + o.x, y + o.y, z + o.z)

    /** Componentwise difference (both in the same frame). */
    public operator fun minus(o: Vector3): Vector3 = Vector3(x - o.x, y - o.y, z - o.z)

    /** Scaled by [s]. */
    public operator fun times(s: Double): Vector3 = Vector3(x * s, y * s, z * s)

    /** Divided by [s]. */
    public operator fun div(s: Double): Vector3 = Vector3(x / s, y / s, z / s)

    /** The opposite vector. */
    public operator fun unaryMinus(): Vector3 = Vector3(-x, -y, -z)

    /** Component by index 0, 1, 2. */
    public operator fun get(i: Int): Double = when (i) {
        0 -> x
        1 -> y
        2 -> z
        else -> throw IndexOutOfBoundsException("Vector3 index $i not in 0..2")
    }

    /** Dot product. */
    public infix fun dot(o: Vector3): Double = x * o.x + y * o.y + z * o.z

    /** Right-handed cross product this × o. */
    public infix fun cross(o: Vector3): Vector3 =
        Vector3(y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x)

    /** Euclidean length, in the unit of the components. */
    public fun norm(): Double = sqrt(x * x + y * y + z * z)

    /** Squared length. */
    public fun normSquared(): Double = x * x + y * y + z * z

    /** True when every component is finite (no NaN, no infinity). */
    public fun isFinite(): Boolean = x.isFinite() && y.isFinite() && z.isFinite()

    /**
     * This vector scaled to unit length.
     * @throws IllegalArgumentException for a zero or non-finite vector, which has no direction.
     */
    public fun normalized(): Vector3 {
        val n = norm()
        require(n > 0.0 && n.isFinite()) { "cannot normalise $this: it has no direction" }
        return Vector3(x / n, y / n, z / n)
    }

    /** [x, y, z]. */
    public fun toDoubleArray(): DoubleArray = doubleArrayOf(x, y, z)

    /** [x, y, z] rounded to float (as Android's SensorEvent.values). */
    public fun toFloatArray(): FloatArray = floatArrayOf(x.toFloat(), y.toFloat(), z.toFloat())

    public companion object {
        /** The zero vector. */
        public val ZERO: Vector3 = Vector3(0.0, 0.0, 0.0)

        /** Unit vector along x. */
        public val UNIT_X: Vector3 = Vector3(1.0, 0.0, 0.0)

        /** Unit vector along y. */
        public val UNIT_Y: Vector3 = Vector3(0.0, 1.0, 0.0)

        /** Unit vector along z. */
        public val UNIT_Z: Vector3 = Vector3(0.0, 0.0, 1.0)

        /** From the first three elements of [a] (e.g. `SensorEvent.values`). */
        public fun of(a: FloatArray): Vector3 {
            require(a.size >= 3) { "need 3 values, got ${a.size}" }
            return Vector3(a[0].toDouble(), a[1].toDouble(), a[2].toDouble())
        }

        /** From the first three elements of [a]. */
        public fun of(a: DoubleArray): Vector3 {
            require(a.size >= 3) { "need 3 values, got ${a.size}" }
            return Vector3(a[0], a[1], a[2])
        }
    }
}
