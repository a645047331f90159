package dev.motionfusion.app.sensor

/**
 * One sensor reading, copied out of the framework's reused `SensorEvent` at once.
 * Values in the device frame and SI units ([SensorKind.unit]); [timestampNs] is
 * `SensorEvent.timestamp` (elapsedRealtimeNanos time base); [accuracy] is
 * `SensorEvent.accuracy` read on every event (SensorManager.SENSOR_STATUS_*).
 * For the rotation vectors, x, y, z are values[0..2] and [w] is values[3] (cos(θ/2));
 * for the other kinds [w] is NaN. [headingAccuracyRad] is values[4] of ROTATION_VECTOR (the
 * estimated heading accuracy, rad, −1 when unknown), NaN otherwise.
 */
data class SensorSample(
    val kind: SensorKind,
    val timestampNs: Long,
    val x: Float,
    val y: Float,
    val z: Float,
    val accuracy: Int,
    val w: Float = Float.NaN,
    val headingAccuracyRad: Float = Float.NaN,
)
