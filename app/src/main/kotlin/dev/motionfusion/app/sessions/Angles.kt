package dev.motionfusion.app.sessions

import kotlin.math.asin
import kotlin.math.atan2

/**
 * Android's azimuth, pitch and roll (as `SensorManager.getOrientation`, degrees) of a
 * quaternion [w, x, y, z] (Hamilton, sensor→ENU), written into [out] at 0..2. The rotation
 * matrix R of q is Android's device→world matrix: azimuth = atan2(R01, R11),
 * pitch = asin(−R21) (clamped), roll = atan2(−R20, R22).
 */
internal fun androidAnglesDeg(w: Double, x: Double, y: Double, z: Double, out: FloatArray) {
    val r01 = 2 * (x * y - w * z)
    val r11 = 1 - 2 * (x * x + z * z)
    val r20 = 2 * (x * z - w * y)
    val r21 = 2 * (y * z + w * x)
    val r22 = 1 - 2 * (x * x + y * y)
    out[0] = Math.toDegrees(atan2(r01, r11)).toFloat()
    out[1] = Math.toDegrees(asin((-r21).coerceIn(-1.0, 1.0))).toFloat()
    out[2] = Math.toDegrees(atan2(-r20, r22)).toFloat()
}
