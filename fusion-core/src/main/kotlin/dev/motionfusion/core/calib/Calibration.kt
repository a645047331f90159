/*
 * Calibration results: immutable values, each with its quality figures. Frames and units as the
 * streams they correct (Android device frame; µT, rad/s, m/s²). File format: CalibrationJson,
 * documented in docs/CALIBRATION.md.
 */
package dev.motionfusion.core.calib

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.event.SessionStream

/** A fit that produced a result, or was refused with a reason. */
public sealed class Fit<out T> {
    public data class Done<out T>(val value: T) : Fit<T>()

    /**
     * Refused: [reason] in English words for a person; [kind] and its [figures] (in the order
     * [RefusalKind] names them) for a program that says it in another language.
     */
    public data class Refused(val reason: String, val kind: RefusalKind = RefusalKind.OTHER, val figures: List<Double> = emptyList()) : Fit<Nothing>()

    /** The value, or null when refused. */
    public fun valueOrNull(): T? = (this as? Done<T>)?.value
}

/** Why a calibration fit was refused, and the figures its reason states ([Fit.Refused.figures], in this order). */
public enum class RefusalKind {
    /** Magnetometer: too few samples kept (samples kept). */
    FEW_SAMPLES,

    /** Magnetometer: the readings do not lie on an ellipsoid (no figures). */
    NO_ELLIPSOID,

    /** Magnetometer: the fitted field is outside the Earth's (fitted µT, lowest µT, highest µT). */
    FIELD_OUT_OF_RANGE,

    /** Magnetometer: the directions cover too little of the sphere (covered %, needed %). */
    FEW_DIRECTIONS,

    /** Magnetometer: the residual is too large a part of the field (residual µT, largest %, field µT). */
    DISTURBED,

    /** Gyroscope: still for too short a time (still s, needed s). */
    NOT_STILL,

    /** Accelerometer: too few distinct still poses (poses, seconds per pose). */
    FEW_POSES,

    /** Accelerometer: an axis never pointed up (axis 0 = x, 1 = y, 2 = z; seconds per pose). */
    AXIS_NEVER_UP,

    /** Accelerometer: an axis never pointed down (axis, seconds per pose). */
    AXIS_NEVER_DOWN,

    /** Accelerometer: the poses do not determine an ellipsoid (no figures). */
    POSES_NO_ELLIPSOID,

    /** Any other reason: only [Fit.Refused.reason] says it. */
    OTHER,
}

/**
 * Hard and soft iron: corrected field = W·(raw − offset), [correction]. The corrected field's
 * magnitude is [fieldStrength] on average.
 *
 * @property stream the stream it was fitted on and applies to (the uncalibrated magnetometer
 *   when recorded: Android's hard-iron correction is then not needed).
 * @property residualRms RMS of |corrected| − [fieldStrength] over the samples, µT.
 * @property coverage fraction (0…1) of the equal-area cells of the sphere of directions that the
 *   corrected field visited.
 * @property magnitudeStdBefore standard deviation of |raw| over the samples, µT.
 * @property magnitudeStdAfter standard deviation of |corrected|, µT.
 */
public data class MagnetometerCalibration(
    val correction: SensorCorrection,
    val stream: SessionStream,
    val model: EllipsoidModel,
    val fieldStrength: Double,
    val residualRms: Double,
    val coverage: Double,
    val samples: Long,
    val magnitudeStdBefore: Double,
    val magnitudeStdAfter: Double,
)

/**
 * Gyroscope bias from still periods: corrected = raw − [bias].
 *
 * @property stillTimeS total time of the still windows used, s.
 * @property biasStdError standard error of the bias per axis from the spread of the windows' means, rad/s.
 * @property noiseStd standard deviation of the rate within still windows per axis, rad/s.
 */
public data class GyroscopeCalibration(
    val bias: Vector3,
    val stream: SessionStream,
    val stillTimeS: Double,
    val stillWindows: Int,
    val biasStdError: Vector3,
    val noiseStd: Vector3,
) {
    val correction: SensorCorrection get() = SensorCorrection(bias)
}

/**
 * Accelerometer offset, scale (and misalignment with [EllipsoidModel.FULL]) from still poses:
 * corrected = W·(raw − offset) has magnitude [gravity] in every pose.
 *
 * @property poses number of distinct still poses used.
 * @property residualRms RMS of |corrected| − [gravity] over the poses, m/s² (0 when the poses
 *   exactly determine the model: 6 poses for AXIS_ALIGNED).
 */
public data class AccelerometerCalibration(
    val correction: SensorCorrection,
    val stream: SessionStream,
    val model: EllipsoidModel,
    val gravity: Double,
    val poses: Int,
    val residualRms: Double,
)

/** All calibrations of one recording; a sensor is null when it was not fitted, with the reason in [refused]. */
public data class Calibration(
    val magnetometer: MagnetometerCalibration? = null,
    val gyroscope: GyroscopeCalibration? = null,
    val accelerometer: AccelerometerCalibration? = null,
    /** Sensor ("magnetometer", "gyroscope", "accelerometer") → why it was not calibrated. */
    val refused: Map<String, String> = emptyMap(),
    /** Who made it (e.g. `fusion calibrate 0.1.0`). */
    val source: String = "",
    /** The recording it was fitted on. */
    val recording: String = "",
    /** The device it was fitted on (the app's guided calibration: maker, model and sensors); empty when unknown. */
    val device: String = "",
) {
    val isEmpty: Boolean get() = magnetometer == null && gyroscope == null && accelerometer == null

    /** The streams the calibration corrects. */
    public fun streams(): Set<SessionStream> = listOfNotNull(magnetometer?.stream, gyroscope?.stream, accelerometer?.stream).toSet()
}
