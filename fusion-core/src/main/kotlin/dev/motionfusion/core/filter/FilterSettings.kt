/*
 * Settings of the Madgwick filter (package dev.motionfusion.core.filter).
 *
 * Frames: sensor readings in the Android device frame (x right, y up along the screen, z out of
 * the screen); the filter works internally in the report's North-West-Up earth frame and outputs
 * in a [WorldFrame]. Units: SI (rad/s, m/s², µT, s); angles in radians.
 */
package dev.motionfusion.core.filter

import dev.motionfusion.core.WorldFrame
import kotlin.math.PI

/** Which sensors the filter fuses. */
public enum class FilterMode {
    /** 6D: gyroscope + accelerometer (the report's IMU update). Heading drifts. */
    IMU,

    /** 9D: gyroscope + accelerometer + magnetometer (the report's MARG update). */
    MARG,
}

/** How the filter starts. */
public enum class Initialisation {
    /** The report's choice: start at the identity and converge at the rate β. */
    IDENTITY,

    /**
     * From the first valid accelerometer sample (inclination) and, in [FilterMode.MARG], the
     * first valid magnetometer sample (heading), as getRotationMatrix does: no transient.
     */
    FIRST_SAMPLE,
}

/**
 * Immutable, validated settings of [MadgwickFilter]. The defaults are the single set chosen by
 * cross-validation over the BROAD and the Tyrex phone trials (docs/ACCURACY.md); [report] gives the
 * report's own filter.
 *
 * A mechanism that can be turned off has a `Double?` setting: null is off, a value is finite and > 0
 * (0 is refused, so off has one form and `copy(zeta = null)` reads as what it does). Kotlin's own
 * optional value, rather than a wrapper type: Java sees a `java.lang.Double` that may be null, and the
 * text forms (`--set NAME=off` or `=0`, a session's metadata, the app's stored settings) map 0 to null
 * ([dev.motionfusion.core.settings.FilterSettingDescriptors]).
 *
 * @property mode 6D or 9D. Default [FilterMode.MARG].
 * @property beta β, gain of the normalised gradient step (eq. 42), rad/s: β = √(3/4)·ω̃_β (eq. 50)
 *   with ω̃_β the gyroscope measurement error; the correction turns the estimate at up to 2β rad/s.
 *   ≥ 0. Default 0.02 (ω̃_β ≈ 1.3°/s), possible because the bias estimates remove most gyroscope bias
 *   and the low-passed accelerometer (accLowPassTime) has little noise left.
 * @property zeta ζ, gain of the report's gyroscope bias drift compensation (eq. 48), rad/s²:
 *   ζ = √(3/4)·ω̃_ζ (eq. 51) with ω̃_ζ the gyroscope drift rate. Acts in the report's MARG steps (headingGain off), as in the report.
 *   null: off. Default off: on real data it hurts (docs/ACCURACY.md); the rest estimate
 *   replaces it.
 * @property initialisation [Initialisation.FIRST_SAMPLE] by default.
 * @property restBiasEstimation estimate the gyroscope bias while the sensor is at rest.
 * @property restGyroThreshold rest when the gyroscope deviates from its low-passed value, and that
 *   value from zero, by less than this, rad/s (see also restMaxRate). Default 3°/s.
 * @property restAccThreshold rest when the accelerometer deviates from its low-passed value by less
 *   than this, m/s². Default 0.5 m/s².
 * @property restMinTime time the rest conditions must hold before rest is declared, s. Default 1.5 s.
 * @property restBiasTime at rest, the bias is the mean gyroscope reading since rest began (the stretch within
 *   restMaxRate that declared it; a rest declared after restImplausibleTime starts from the rate low-passed over
 *   0.5 s), for up to this long, then a moving average with this time constant, s. Default 2 s.
 * @property restMaxRate a rest's plausibility: rest is declared after restMinTime only if the low-passed
 *   gyroscope (what the rest estimate takes as the bias) has stayed within this of zero for that long, rad/s;
 *   a larger mean rate needs the rest conditions held for restImplausibleTime. A slow turn below
 *   restGyroThreshold (a phone carried upright, in a bag, an elevator ride) otherwise passes as a rest, its
 *   rate is taken as the bias and the heading then drifts at that rate; with iOS's bias-corrected rates this
 *   cost OxIOD 1–3° per group (docs/ACCURACY.md). Default 0.015 rad/s (0.86°/s).
 * @property restImplausibleTime see restMaxRate: how long the rest conditions must hold with a mean rate
 *   beyond restMaxRate (a real bias that large, as of an uncalibrated gyroscope, is still estimated), s; at
 *   most restMinTime turns the check off. Default 5 s.
 * @property magDisturbanceRejection ignore the magnetometer while its magnitude or dip angle
 *   departs from a learned reference (the gyroscope then holds heading). Default off: indoors a
 *   phone's field varies by more than the tolerances and the rejection then costs more heading
 *   than it saves (docs/ACCURACY.md); on for a sensor with a magnet near it.
 * @property magNormTolerance allowed relative deviation of the field magnitude from the reference.
 *   Default 0.1 (10 %).
 * @property magDipTolerance allowed deviation of the dip angle from the reference, rad. Default 10°.
 * @property magMaxRejectionTime after this long continuously disturbed, the current field becomes
 *   the new reference (a new environment), s; with magRejectionFactor, the budget of the hold instead.
 *   Default 60 s.
 * @property magReferenceTime time constant with which the reference follows an undisturbed field,
 *   s. Default 20 s.
 * @property accRejection skip the accelerometer correction during strong non-gravitational
 *   acceleration. Default off: on BROAD it costs more (drift while rejected) than it saves.
 * @property accNormTolerance reject when ‖a‖ departs from standard gravity by more than this, m/s².
 *   Default 2 m/s².
 * @property accAngleTolerance reject when a is further than this from the estimated up, rad.
 *   Default 10°.
 * @property accMaxRejectionTime after this long continuously rejected, the accelerometer is trusted
 *   again (recovery from a wrong estimate), s. Default 5 s.
 * @property outputFrame earth frame of [MadgwickFilter.orientation]. Default [WorldFrame.ENU] (Android's
 *   world); [WorldFrame.NWU] is the report's, [WorldFrame.NED] the aerospace one.
 * @property headingGain heading correction apart from inclination, 1/s: with a magnetometer the
 *   estimate turns about the vertical towards magnetic north at this fraction of the heading error
 *   per second (time constant 1/headingGain), and the accelerometer alone corrects inclination with
 *   β. null (off) gives the report's MARG step, where one normalised gradient corrects both. Default
 *   0.08 (12.5 s; chosen with motionBiasGain by leaving one data set out, docs/ACCURACY.md).
 * @property motionBiasGain gyroscope bias estimation during motion (needs headingGain on), rad/s
 *   per unit heading error and second: the heading error sin δ, a rate about the estimated vertical,
 *   is integrated into the bias (a PI observer), so a bias is learnt without rest. null: off.
 *   Default 0.0015.
 * @property motionBiasRestTime after the rest estimate has acted, the motion estimate's gain ramps
 *   up from 0 to motionBiasGain over this time, s: a bias measured at rest is better than one
 *   inferred from heading errors until it may have drifted. 0: full gain at once. Default 300 s.
 * @property motionBiasLimit each axis of the bias stays within ±this, rad/s. Default 2°/s.
 * @property headingRecoveryTime for this long after the start and after the magnetometer gets a new
 *   reference, while the heading error is large (from above 2° until below 0.5°), the heading gain is
 *   at least 1/t (t the time since then, s), so a wrong first heading converges within seconds. null:
 *   off. Default 10 s.
 * @property magTrustSpread magnetic trust (MagneticTrust.kt): with σ² the field's wander (the mean square
 *   departure of its magnitude, as a ratio, and of the sine of its dip from their means over magTrustTime) and
 *   r = min(1, magTrustSpread/σ), the heading gain is scaled by r and the bias estimate in motion by r³. Indoors,
 *   where a walk through a building meets a field that wanders, the heading is then held by the gyroscope. null:
 *   off. Default off: it wins on walks through buildings (ADVIO) and loses where the phone
 *   turns in one room (Tyrex, OxIOD); [BUILDINGS_TRUST_SPREAD] is the value for the former (docs/ACCURACY.md).
 * @property magTrustTime with magTrustSpread, the time the field's means and wander are low-passed over, s.
 *   Default 10 s.
 * @property hardIronThreshold the magnetometer's hard-iron offset estimated from the recording (HardIronEstimate.kt:
 *   the field's change against what the gyroscope's rotation predicts) and taken off every reading, shrunk by
 *   this length, µT: an estimate shorter than it takes nothing off. null: off.
 * @property hardIronTime with hardIronThreshold, the time over which older turns are forgotten, s. null: never.
 * @property magNewFieldTime with magDisturbanceRejection, a disturbed field that stays within the
 *   tolerances of its own running mean for this long is trusted as the new reference, s. null: off
 *   (then only magMaxRejectionTime ends a rejection). Default off.
 * @property magNewFieldMinGyro with magNewFieldTime, the steady time of a new field counts only while the
 *   bias-corrected rate is at least this, rad/s: a disturbed field that stays steady because the phone lies
 *   still (a magnet beside it on a table) is not learnt; one that stays steady while the phone turns is a
 *   new environment. null (off): any motion counts. Default off.
 * @property magResumeTime with magDisturbanceRejection, the heading gain comes back from 0 to headingGain
 *   linearly over this time after a disturbance ends or a new reference is taken, s, instead of at once (and
 *   a new reference then does not restart the fast heading convergence): the heading carried by the
 *   gyroscope is pulled onto the field without a jump. null (off): at once, as before. Default off.
 * @property magRejectionFactor with magDisturbanceRejection, a hold limited in time: the time rejected
 *   counts up while the field is disturbed and down at this factor while it is not; once it exceeds
 *   magMaxRejectionTime the disturbed field is used again at headingGain divided by this factor, and the
 *   reference stays (VQF's counting). null (off): after magMaxRejectionTime continuously disturbed the field
 *   of that moment becomes the reference, as before. Default off.
 * @property magFirstFieldTime with magDisturbanceRejection, the first reading is not the reference: the
 *   field is used until one has stayed within the tolerances of its own running mean for this long
 *   (counted as for magNewFieldMinGyro), which becomes the reference, s. null (off): the first reading.
 *   Default off.
 * @property magUndisturbedTime with magDisturbanceRejection, a disturbance ends only once the field has
 *   agreed with the reference for this long, s. null (off): at once. Default off.
 * @property inclinationRecoveryBeta re-convergence of inclination after violent motion, rad/s: at the
 *   start (a first reading taken in motion) and after a saturated gyroscope reading (gyroSaturation),
 *   once the accelerometer's magnitude has stayed within accNormTolerance of standard gravity for
 *   accTrustTime, the step gain is this instead of β (at most 2× this rad/s of correction) until the
 *   accelerometer (low-passed with accLowPassTime) is within 1° of the estimated up, for at most 10 s;
 *   then β again. null: off. Default 0.5 (up to 57°/s).
 * @property accTrustTime see inclinationRecoveryBeta, s. Default 0.5 s.
 * @property recoveryAngle inclination recovery after any large error (with inclinationRecoveryBeta on):
 *   once the phone has been near-still for recoveryStillTime (the bias-corrected gyroscope below
 *   recoveryGyroThreshold, the accelerometer's magnitude within restAccThreshold of standard gravity), an
 *   estimated up further than this from the accelerometer arms the recovery at once (the low-passed
 *   accelerometer starts again from the still readings), whatever put the estimate off: an impact, a
 *   shake, a fall, a throw. rad, below π; null: off. Default 1°.
 * @property recoveryGyroThreshold see recoveryAngle, rad/s. Default 0.1 rad/s (5.7°/s).
 * @property recoveryStillTime see recoveryAngle, s. Default 0.2 s.
 * @property accLowPassTime inclination from the accelerometer low-passed in a quasi-inertial frame, s:
 *   the readings, turned with the gyroscope into a frame fixed in space, are low-passed with this time
 *   constant and the correction steps use the result instead of the raw reading. Gravity is fixed in that
 *   frame and passes; linear acceleration, whose integral (a velocity) stays bounded, averages out
 *   (the idea of VQF, Laidig & Seel 2023). null: off (the raw reading, as in the report).
 *   Default 5 s.
 * @property gyroSaturation a gyroscope reading with an axis at or beyond this, rad/s, is taken as clipped
 *   at the sensor's range: the low-passed accelerometer starts again, inclination recovery
 *   (inclinationRecoveryBeta) is armed and fast heading convergence (headingRecoveryTime) starts again.
 *   Set it just below the sensor's range (Android: Sensor.getMaximumRange()). null: off.
 *   Default 34 rad/s, just below the ±2000°/s (34.9 rad/s) of most phones and IMUs.
 * @property maxGap longest accepted time between samples, s: a longer gyroscope gap is not
 *   integrated, and the filter then recovers as after a saturated reading (gyroSaturation), since the
 *   phone may have turned any way meanwhile; an accelerometer or magnetometer sample older than this is
 *   not used. Default 0.5 s.
 */
public data class FilterSettings(
    val mode: FilterMode = FilterMode.MARG,
    val beta: Double = 0.02,
    val zeta: Double? = null,
    val initialisation: Initialisation = Initialisation.FIRST_SAMPLE,
    val restBiasEstimation: Boolean = true,
    val restGyroThreshold: Double = 3.0 * DEG,
    val restAccThreshold: Double = 0.5,
    val restMinTime: Double = 1.5,
    val restBiasTime: Double = 2.0,
    val restMaxRate: Double = 0.015,
    val restImplausibleTime: Double = 5.0,
    val magDisturbanceRejection: Boolean = false,
    val magNormTolerance: Double = 0.1,
    val magDipTolerance: Double = 10.0 * DEG,
    val magMaxRejectionTime: Double = 60.0,
    val magReferenceTime: Double = 20.0,
    val magNewFieldTime: Double? = null,
    val magNewFieldMinGyro: Double? = null,
    val magResumeTime: Double? = null,
    val magRejectionFactor: Double? = null,
    val magFirstFieldTime: Double? = null,
    val magUndisturbedTime: Double? = null,
    val magTrustSpread: Double? = null,
    val magTrustTime: Double = 10.0,
    val hardIronThreshold: Double? = 1.5,
    val hardIronTime: Double? = 600.0,
    val accRejection: Boolean = false,
    val accNormTolerance: Double = 2.0,
    val accAngleTolerance: Double = 10.0 * DEG,
    val accMaxRejectionTime: Double = 5.0,
    val inclinationRecoveryBeta: Double? = 0.5,
    val accTrustTime: Double = 0.5,
    val recoveryAngle: Double? = 1.0 * DEG,
    val recoveryGyroThreshold: Double = 0.1,
    val recoveryStillTime: Double = 0.2,
    val accLowPassTime: Double? = 5.0,
    val gyroSaturation: Double? = 34.0,
    val headingGain: Double? = 0.08,
    val headingRecoveryTime: Double? = 10.0,
    val motionBiasGain: Double? = 0.0015,
    val motionBiasRestTime: Double = 300.0,
    val motionBiasLimit: Double = 2.0 * DEG,
    val outputFrame: WorldFrame = WorldFrame.ENU,
    val maxGap: Double = 0.5,
) {
    init {
        requireFinite("beta", beta, min = 0.0)
        requireOnOrOff("zeta", zeta)
        requirePositive("restGyroThreshold", restGyroThreshold)
        requirePositive("restAccThreshold", restAccThreshold)
        requireFinite("restMinTime", restMinTime, min = 0.0)
        requirePositive("restBiasTime", restBiasTime)
        requirePositive("restMaxRate", restMaxRate)
        requireFinite("restImplausibleTime", restImplausibleTime, min = 0.0)
        requirePositive("magNormTolerance", magNormTolerance)
        require(magDipTolerance > 0.0 && magDipTolerance < PI / 2) { "magDipTolerance must be in (0, π/2) rad: $magDipTolerance" }
        requirePositive("magMaxRejectionTime", magMaxRejectionTime)
        requirePositive("magReferenceTime", magReferenceTime)
        requirePositive("accNormTolerance", accNormTolerance)
        require(accAngleTolerance > 0.0 && accAngleTolerance < PI) { "accAngleTolerance must be in (0, π) rad: $accAngleTolerance" }
        requirePositive("accMaxRejectionTime", accMaxRejectionTime)
        requirePositive("maxGap", maxGap)
        requireOnOrOff("headingGain", headingGain)
        requireOnOrOff("motionBiasGain", motionBiasGain)
        requireOnOrOff("headingRecoveryTime", headingRecoveryTime)
        requireOnOrOff("magTrustSpread", magTrustSpread)
        requirePositive("magTrustTime", magTrustTime)
        requireOnOrOff("hardIronThreshold", hardIronThreshold)
        requireOnOrOff("hardIronTime", hardIronTime)
        requireOnOrOff("magNewFieldTime", magNewFieldTime)
        requireOnOrOff("magNewFieldMinGyro", magNewFieldMinGyro)
        requireOnOrOff("magResumeTime", magResumeTime)
        requireOnOrOff("magRejectionFactor", magRejectionFactor)
        requireOnOrOff("magFirstFieldTime", magFirstFieldTime)
        requireOnOrOff("magUndisturbedTime", magUndisturbedTime)
        requireOnOrOff("inclinationRecoveryBeta", inclinationRecoveryBeta)
        requirePositive("accTrustTime", accTrustTime)
        require(recoveryAngle == null || recoveryAngle > 0.0 && recoveryAngle < PI) { "recoveryAngle must be in (0, π) rad, or null for off: $recoveryAngle" }
        requirePositive("recoveryGyroThreshold", recoveryGyroThreshold)
        requireFinite("recoveryStillTime", recoveryStillTime, min = 0.0)
        requireOnOrOff("accLowPassTime", accLowPassTime)
        requireOnOrOff("gyroSaturation", gyroSaturation)
        requirePositive("motionBiasLimit", motionBiasLimit)
        requireFinite("motionBiasRestTime", motionBiasRestTime, min = 0.0)
    }

    public companion object {
        /**
         * The report's filter exactly: β for ω̃_β = 5°/s and ζ for ω̃_ζ = 0.2°/s² as in its
         * listing (eqs. 50–51; ζ acts in MARG steps only), identity start, none of the additions.
         */
        @JvmStatic
        @JvmOverloads
        public fun report(mode: FilterMode = FilterMode.MARG): FilterSettings = FilterSettings(
            mode = mode,
            beta = SQRT_3_4 * 5.0 * DEG,
            zeta = SQRT_3_4 * 0.2 * DEG,
            initialisation = Initialisation.IDENTITY,
            restBiasEstimation = false,
            magDisturbanceRejection = false,
            accRejection = false,
            headingGain = null,
            motionBiasGain = null,
            headingRecoveryTime = null,
            magNewFieldTime = null,
            hardIronThreshold = null,
            inclinationRecoveryBeta = null,
            recoveryAngle = null,
            accLowPassTime = null,
            gyroSaturation = null,
        )

        /**
         * magTrustSpread for walks through buildings (a mall, a station, offices): the value chosen on ADVIO
         * (docs/ACCURACY.md, "Walks through buildings"); the app's "Walking through buildings" switch sets it.
         */
        public const val BUILDINGS_TRUST_SPREAD: Double = 0.005

        private const val DEG = PI / 180.0
        private val SQRT_3_4 = kotlin.math.sqrt(0.75)

        private fun requireFinite(name: String, v: Double, min: Double) =
            require(v.isFinite() && v >= min) { "$name must be finite and ≥ $min: $v" }

        private fun requirePositive(name: String, v: Double) =
            require(v.isFinite() && v > 0.0) { "$name must be finite and > 0: $v" }

        /** A mechanism's setting: null (off) or finite and > 0; 0 is refused, so off has one form. */
        private fun requireOnOrOff(name: String, v: Double?) =
            require(v == null || v.isFinite() && v > 0.0) { "$name must be finite and > 0, or null for off: $v" }
    }
}
