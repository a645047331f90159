package dev.motionfusion.app.live

import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.core.Quaternion
import dev.motionfusion.app.settings.AngleConvention
import dev.motionfusion.app.fusion.FusionMode
import dev.motionfusion.app.fusion.FusionState

/** Why the heading may be wrong. */
enum class MagWarning {
    /** The magnetometer's event.accuracy is UNRELIABLE or LOW: calibrate (figure 8). */
    LOW_ACCURACY,

    /** The field strength is outside the Earth's range: something magnetic nearby. */
    FIELD_STRENGTH,

    /** The filter's disturbance detector has left the magnetometer out. */
    DISTURBED,
}

/** How far the heading shown can be trusted. */
enum class HeadingQuality { NONE, RELATIVE, WARNING, OK }

/**
 * What one frame of the live screen shows, computed from a [FusionState] and the display
 * rotation (Surface.ROTATION_*: 0..3). Pure: tested on the JVM.
 *
 * @property angles the Madgwick (or fallback) orientation in the chosen convention.
 * @property attitude aerospace pitch and roll for the attitude indicator.
 * @property headingDeg the heading of the screen's top edge, 0..360.
 * @property rotationVectorAngles the phone's ROTATION_VECTOR in the same convention.
 * @property differenceDeg angle of the rotation between Madgwick and ROTATION_VECTOR, 0..180°.
 * @property tiltDifferenceDeg angle between their up directions, 0..180° (blind to heading).
 * @property gameTiltDifferenceDeg same against GAME_ROTATION_VECTOR.
 * @property magWarnings what is wrong with the magnetometer now (empty when fine or absent).
 * @property orientation the fused orientation itself (device → ENU, [w, x, y, z]), for the 3D model.
 * @property rotationVector the phone's own ROTATION_VECTOR (device → ENU), drawn as a ghost beside it.
 */
data class LiveUiState(
    val angles: DisplayAngles?,
    val attitude: DisplayAngles?,
    val headingDeg: Double?,
    val headingQuality: HeadingQuality,
    val rotationVectorAngles: DisplayAngles?,
    val differenceDeg: Double?,
    val tiltDifferenceDeg: Double?,
    val gameTiltDifferenceDeg: Double?,
    val magWarnings: Set<MagWarning>,
    val orientation: Quaternion? = null,
    val rotationVector: Quaternion? = null,
) {
    /**
     * A figure-8 calibration hint is worth showing: the phone's own calibration is in doubt (its accuracy, a field
     * beyond the Earth's). Not for a disturbance alone: a magnet or a building's steel is not calibrated away.
     */
    val showCalibrationHint: Boolean get() = magWarnings.any { it != MagWarning.DISTURBED }

    companion object {
        /** The Earth's field at the surface spans about 25 to 65 µT. */
        const val EARTH_FIELD_MIN_UT = 25.0
        const val EARTH_FIELD_MAX_UT = 65.0

        /** SensorManager.SENSOR_STATUS_ACCURACY_MEDIUM: below it the magnetometer wants calibration. */
        const val ACCURACY_MEDIUM = 2

        fun of(s: FusionState, displayRotation: Int): LiveUiState {
            val convention = s.settings.convention
            val q = s.orientation
            val rv = s.rotationVector
            val mode = s.mode.mode
            val warnings = LinkedHashSet<MagWarning>()
            val mag = s.sensors[SensorKind.MAGNETOMETER]
            if (mag != null && mode.hasMagneticHeading) {
                if (mag.accuracy in 0 until ACCURACY_MEDIUM) warnings += MagWarning.LOW_ACCURACY
                val f = s.magneticFieldUt
                if (f != null && (f < EARTH_FIELD_MIN_UT || f > EARTH_FIELD_MAX_UT)) warnings += MagWarning.FIELD_STRENGTH
                if (s.magneticDisturbance) warnings += MagWarning.DISTURBED
            }
            val angles = q?.let { Readout.angles(it, displayRotation, convention) }
            val heading = q?.let { Readout.angles(it, displayRotation, AngleConvention.ANDROID).yaw }
            val quality = when {
                q == null || mode == FusionMode.TILT_ONLY || mode == FusionMode.NONE -> HeadingQuality.NONE
                !mode.hasMagneticHeading -> HeadingQuality.RELATIVE
                warnings.isNotEmpty() -> HeadingQuality.WARNING
                else -> HeadingQuality.OK
            }
            return LiveUiState(
                angles = angles,
                attitude = q?.let { Readout.attitude(it, displayRotation) },
                headingDeg = if (quality == HeadingQuality.NONE) null else heading,
                headingQuality = quality,
                rotationVectorAngles = rv?.let { Readout.angles(it, displayRotation, convention) },
                differenceDeg = if (q != null && rv != null) Readout.angleBetweenDeg(q, rv) else null,
                tiltDifferenceDeg = if (q != null && rv != null) Readout.tiltBetweenDeg(q, rv) else null,
                gameTiltDifferenceDeg = s.gameRotationVector?.let { g -> q?.let { Readout.tiltBetweenDeg(it, g) } },
                magWarnings = warnings,
                orientation = q,
                rotationVector = rv,
            )
        }
    }
}
