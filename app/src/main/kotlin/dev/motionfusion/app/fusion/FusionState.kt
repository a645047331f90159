package dev.motionfusion.app.fusion

import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.core.Quaternion
import dev.motionfusion.app.settings.LiveSettings

/**
 * Per-sensor figures at one instant: [samples] seen, achieved [rateHz] and [jitterMs] (standard
 * deviation of the intervals) over the last intervals, duplicate and backward timestamps, the
 * last `event.accuracy` (SensorManager.SENSOR_STATUS_*) and the last values (x, y, z, w; w NaN
 * except for rotation vectors).
 */
data class SensorStats(
    val samples: Long,
    val rateHz: Double,
    val jitterMs: Double,
    val duplicates: Long,
    val backwards: Long,
    val accuracy: Int,
    val x: Float,
    val y: Float,
    val z: Float,
    val w: Float,
)

/**
 * What the fusion engine has computed, published for the UI (which may sample it).
 *
 * Orientations are unit quaternions [w, x, y, z], Hamilton, device → East-North-Up (as the
 * rotation vector sensor); null until there is one.
 * @property mode how [orientation] is computed and why.
 * @property orientation the Madgwick (or fallback) estimate.
 * @property rotationVector the phone's own TYPE_ROTATION_VECTOR.
 * @property rotationVectorHeadingAccuracyRad the rotation vector's own heading accuracy
 *   estimate (values[4]), rad; null when the phone gives none.
 * @property gameRotationVector the phone's own TYPE_GAME_ROTATION_VECTOR (heading arbitrary).
 * @property magneticFieldUt strength of the last magnetometer reading, µT.
 * @property atRest, [magneticDisturbance], [accelerometerRejected]: the filter's flags.
 * @property gyroBiasRadS the filter's gyroscope bias estimate, rad/s, device frame.
 * @property filterSteps gyroscope samples integrated since the filter was (re)built.
 * @property timestampNs event time of the last sample folded in (elapsedRealtimeNanos base).
 */
data class FusionState(
    val mode: EffectiveMode,
    val settings: LiveSettings,
    val orientation: Quaternion?,
    val rotationVector: Quaternion?,
    val rotationVectorHeadingAccuracyRad: Double?,
    val gameRotationVector: Quaternion?,
    val sensors: Map<SensorKind, SensorStats>,
    val magneticFieldUt: Double?,
    val atRest: Boolean,
    val magneticDisturbance: Boolean,
    val accelerometerRejected: Boolean,
    val gyroBiasRadS: DoubleArray?,
    val filterSteps: Long,
    val timestampNs: Long,
) {
    override fun equals(other: Any?): Boolean = this === other
    override fun hashCode(): Int = System.identityHashCode(this)
}
