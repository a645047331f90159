package dev.motionfusion.app.live

import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.sensor.SensorSample
import dev.motionfusion.core.sensormanager.SensorManagerMath

/**
 * Android's azimuth/pitch/roll from the latest accelerometer and magnetometer readings,
 * computed as `SensorManager.getRotationMatrix` + `getOrientation` do, with fusion-core's
 * ports. Azimuth is measured from magnetic north towards east. Holds its arrays: no
 * allocation per sample.
 */
class AccMagOrientation {
    private val gravity = FloatArray(3)
    private val geomagnetic = FloatArray(3)
    private val r = FloatArray(9)
    private val angles = FloatArray(3)
    private var hasGravity = false
    private var hasField = false

    /** Takes an accelerometer or magnetometer sample; others are ignored. */
    fun update(s: SensorSample) {
        when (s.kind) {
            SensorKind.ACCELEROMETER -> { gravity[0] = s.x; gravity[1] = s.y; gravity[2] = s.z; hasGravity = true }
            SensorKind.MAGNETOMETER -> { geomagnetic[0] = s.x; geomagnetic[1] = s.y; geomagnetic[2] = s.z; hasField = true }
            SensorKind.GYROSCOPE -> Unit
        }
    }

    /** The current angles, or why there are none. */
    fun current(): OrientationReading {
        if (!hasGravity || !hasField) return OrientationReading.Waiting
        if (!SensorManagerMath.getRotationMatrix(r, null, gravity, geomagnetic)) return OrientationReading.Undefined
        SensorManagerMath.getOrientation(r, angles)
        return OrientationReading.Angles(
            azimuthDeg = (Math.toDegrees(angles[0].toDouble()) + 360.0) % 360.0,
            pitchDeg = Math.toDegrees(angles[1].toDouble()),
            rollDeg = Math.toDegrees(angles[2].toDouble()),
        )
    }
}

/** What the orientation display shows. */
sealed interface OrientationReading {
    /** Accelerometer or magnetometer has not reported yet. */
    data object Waiting : OrientationReading

    /** Free fall, or the field is (nearly) parallel to gravity: no heading can be defined. */
    data object Undefined : OrientationReading

    /** Android azimuth (0..360 from magnetic north), pitch and roll, degrees. */
    data class Angles(val azimuthDeg: Double, val pitchDeg: Double, val rollDeg: Double) : OrientationReading
}
