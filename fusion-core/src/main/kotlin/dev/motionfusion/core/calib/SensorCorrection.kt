/*
 * The correction of one three-axis sensor: corrected = W · (raw − offset), in the sensor's own
 * unit and the Android device frame. W is symmetric (a rotation part cannot be observed from
 * magnitudes alone, docs/CALIBRATION.md); the identity for an offset-only correction such as a
 * gyroscope bias.
 */
package dev.motionfusion.core.calib

import dev.motionfusion.core.Vector3

/** corrected = [matrix] · (raw − [offset]). Immutable; [apply] for callers, [applyInPlace] for the per-sample path. */
public class SensorCorrection(
    /** Subtracted first (hard iron, accelerometer offset, gyroscope bias), in the sensor's unit. */
    public val offset: Vector3,
    /** Applied after the offset (soft iron, scale and misalignment); identity for offset only. */
    public val matrix: Matrix3 = Matrix3.IDENTITY,
) {
    init {
        require(offset.isFinite() && matrix.isFinite()) { "calibration values must be finite" }
    }

    private val o = offset.toDoubleArray()
    private val w = DoubleArray(9).also { matrix.copyInto(it) }

    public fun apply(raw: Vector3): Vector3 = matrix * (raw - offset)

    /** Corrects values[at], values[at + 1], values[at + 2] in place; allocates nothing. */
    public fun applyInPlace(values: DoubleArray, at: Int = 0) {
        val x = values[at] - o[0]
        val y = values[at + 1] - o[1]
        val z = values[at + 2] - o[2]
        values[at] = w[0] * x + w[1] * y + w[2] * z
        values[at + 1] = w[3] * x + w[4] * y + w[5] * z
        values[at + 2] = w[6] * x + w[7] * y + w[8] * z
    }

    override fun equals(other: Any?): Boolean = other is SensorCorrection && offset == other.offset && matrix == other.matrix
    override fun hashCode(): Int = 31 * offset.hashCode() + matrix.hashCode()
    override fun toString(): String = "SensorCorrection(offset=$offset, matrix=$matrix)"
}
