/*
 * The one table of FilterSettings by name: the command line's `--set NAME=VALUE` and `name=value`
 * overrides, the session metadata's `filter_settings` object and the app's stored settings all go
 * through it, so a new setting is added here once. It lives apart from the filter (package `filter`):
 * the names, JSON keys, titles, sections and slider ranges are for the tools and screens around the
 * filter, which itself reads only [FilterSettings].
 */
package dev.motionfusion.core.settings

import dev.motionfusion.core.WorldFrame
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.Initialisation

/** What kind of value a setting holds. */
public enum class SettingKind {
    /** A finite number in the setting's [FilterSettingDescriptor.unit]. */
    NUMBER,

    /** true or false. */
    BOOLEAN,

    /** One of [FilterSettingDescriptor.choices], by name. */
    CHOICE,
}

/** Which part of the filter a setting belongs to, for a settings screen's sections. */
public enum class SettingGroup {
    /** Mode, start, the correction gains (β, ζ, heading) and the output. */
    GAINS,

    /** Magnetic disturbance and accelerometer rejection. */
    REJECTION,

    /** Gyroscope bias estimation, at rest and in motion. */
    BIAS,

    /** The low-passed accelerometer and the inclination recovery it feeds. */
    LOW_PASS,

    /** The gyroscope's clipping at its range and gaps between samples. */
    SATURATION,
}

/**
 * One property of [FilterSettings].
 *
 * @property name the Kotlin property name, as `--set NAME=VALUE` takes it.
 * @property jsonKey the member name in a session's metadata (`filter_settings`).
 * @property unit SI unit of a number ("" for a ratio, a flag or a choice).
 * @property kind number, flag or choice; [choices] lists the names of a choice.
 * @property title a short English name for a settings screen ("β, correction gain").
 * @property group the section it belongs to.
 * @property range a number's useful span to set by hand, in [unit] (a slider's ends; FilterSettings
 *   itself accepts more); null for a flag or a choice.
 * @property limits the values a number may take at all, in [unit]: from 0 to [LIMIT_FACTOR] times the
 *   end of [range]; beyond it no filter behaves meaningfully, and [with] refuses it, naming the limits.
 * @property zeroDisables true when the setting can be off: null in [FilterSettings], and in text 0 (the form
 *   of off since the first version, kept in files) or "off" (a screen shows a switch beside the value).
 */
public class FilterSettingDescriptor internal constructor(
    public val name: String,
    public val jsonKey: String,
    public val unit: String,
    public val kind: SettingKind,
    public val choices: List<String>,
    private val read: (FilterSettings) -> Any?,
    private val write: (FilterSettings, Any?) -> FilterSettings,
    private val absent: Any?,
    public val title: String,
    public val group: SettingGroup,
    public val range: ClosedFloatingPointRange<Double>?,
    public val zeroDisables: Boolean,
) {
    public val limits: ClosedFloatingPointRange<Double>? = range?.let { 0.0..(it.endInclusive * LIMIT_FACTOR) }

    /** The value in [s]: a Double (null when the setting is off, [zeroDisables]), a Boolean, or the name of a choice. */
    public fun value(s: FilterSettings): Any? = read(s)

    /** The value in the default [FilterSettings] (null: off). */
    public val default: Any? get() = read(DEFAULTS)

    /**
     * The value in [s] as files keep it (a session's metadata, the app's stored settings): [value], with
     * off written 0, the form every version of those files has used and read back as off.
     */
    public fun storedValue(s: FilterSettings): Any = read(s) ?: 0.0

    /**
     * [s] with this setting set to [value] (Double or other Number, Boolean, or a choice's name). A
     * setting that can be off ([zeroDisables]) is turned off by null, 0 or "off".
     * @throws IllegalArgumentException for a value of the wrong kind or one the settings reject.
     */
    public fun with(s: FilterSettings, value: Any?): FilterSettings {
        val v: Any? = when (kind) {
            SettingKind.NUMBER -> if (zeroDisables && isOff(value)) null else ((value as? Number)?.toDouble() ?: throw IllegalArgumentException("$name expects a number${if (zeroDisables) " or off" else ""}, got $value")).also { d ->
                val l = limits
                if (l != null && d.isFinite() && d !in l) throw IllegalArgumentException("$name must be within ${num(l.start)}–${num(l.endInclusive)}${if (unit.isEmpty()) "" else " $unit"}: $value")
            }
            SettingKind.BOOLEAN -> value as? Boolean ?: throw IllegalArgumentException("$name expects true or false, got $value")
            SettingKind.CHOICE -> (value as? String)?.takeIf { it in choices } ?: throw IllegalArgumentException("$name expects one of ${choices.joinToString()}, got $value")
        }
        return write(s, v)
    }

    /**
     * [s] with this setting parsed from [text] (a number, "off" or 0 for a setting that can be off,
     * true/false, or a choice's name).
     * @throws IllegalArgumentException for text that does not parse or a value the settings reject.
     */
    public fun withText(s: FilterSettings, text: String): FilterSettings = with(
        s,
        when (kind) {
            SettingKind.NUMBER -> if (zeroDisables && isOff(text)) null
                else text.trim().toDoubleOrNull() ?: throw IllegalArgumentException("$name expects a number${if (zeroDisables) " or off" else ""}, got '$text'")
            SettingKind.BOOLEAN -> text.trim().toBooleanStrictOrNull() ?: throw IllegalArgumentException("$name expects true or false, got '$text'")
            SettingKind.CHOICE -> text.trim()
        },
    )

    /**
     * The value to assume when stored settings lack this member: settings added after a session
     * was recorded take the value that reproduces the filter of that time (the mechanism off);
     * null means the current default.
     */
    public val valueWhenAbsent: Any? get() = absent

    override fun toString(): String = name

    public companion object {
        private val DEFAULTS = FilterSettings()

        /** How far beyond a slider's end a setting may still be set ([limits]). */
        public const val LIMIT_FACTOR: Double = 100.0

        /** The text that turns a setting off, besides 0. */
        public const val OFF: String = "off"

        private fun isOff(v: Any?): Boolean = v == null || (v is Number && v.toDouble() == 0.0) || (v is String && v.trim().equals(OFF, ignoreCase = true))

        private fun num(v: Double): String = if (v == Math.rint(v) && kotlin.math.abs(v) < 1e15) v.toLong().toString() else v.toString()
    }
}

private typealias G = SettingGroup

/** All properties of [FilterSettings], in declaration order. */
public object FilterSettingDescriptors {
    public val all: List<FilterSettingDescriptor> = listOf(
        choice("mode", "mode", G.GAINS, "Sensors fused (MARG 9D, IMU 6D)", FilterMode.entries.map { it.name }, { it.mode.name }) { s, v -> s.copy(mode = FilterMode.valueOf(v)) },
        number("beta", "beta", "rad/s", G.GAINS, "β, correction gain", 0.0..0.5, { it.beta }) { s, v -> s.copy(beta = v) },
        offable("zeta", "zeta", "rad/s²", G.GAINS, "ζ, gyroscope drift compensation", 0.0..0.05, { it.zeta }) { s, v -> s.copy(zeta = v) },
        choice("initialisation", "initialisation", G.GAINS, "Start", Initialisation.entries.map { it.name }, { it.initialisation.name }) { s, v -> s.copy(initialisation = Initialisation.valueOf(v)) },
        flag("restBiasEstimation", "rest_bias_estimation", G.BIAS, "Estimate the gyroscope bias at rest", { it.restBiasEstimation }) { s, v -> s.copy(restBiasEstimation = v) },
        number("restGyroThreshold", "rest_gyro_threshold_rad_s", "rad/s", G.BIAS, "Rest: gyroscope within", 0.005..0.2, { it.restGyroThreshold }) { s, v -> s.copy(restGyroThreshold = v) },
        number("restAccThreshold", "rest_acc_threshold_m_s2", "m/s²", G.BIAS, "Rest: accelerometer within", 0.05..2.0, { it.restAccThreshold }) { s, v -> s.copy(restAccThreshold = v) },
        number("restMinTime", "rest_min_time_s", "s", G.BIAS, "Rest: held for", 0.0..10.0, { it.restMinTime }) { s, v -> s.copy(restMinTime = v) },
        number("restBiasTime", "rest_bias_time_s", "s", G.BIAS, "Rest: bias averaged over", 0.1..20.0, { it.restBiasTime }) { s, v -> s.copy(restBiasTime = v) },
        number("restMaxRate", "rest_max_rate_rad_s", "rad/s", G.BIAS, "Rest: mean rate (the bias) within", 0.002..0.2, { it.restMaxRate }) { s, v -> s.copy(restMaxRate = v) },
        number("restImplausibleTime", "rest_implausible_time_s", "s", G.BIAS, "Rest beyond that mean rate: held for", 0.0..60.0, { it.restImplausibleTime }) { s, v -> s.copy(restImplausibleTime = v) },
        flag("magDisturbanceRejection", "mag_disturbance_rejection", G.REJECTION, "Ignore a disturbed magnetic field", { it.magDisturbanceRejection }) { s, v -> s.copy(magDisturbanceRejection = v) },
        number("magNormTolerance", "mag_norm_tolerance", "", G.REJECTION, "Field strength tolerance (ratio)", 0.01..0.5, { it.magNormTolerance }) { s, v -> s.copy(magNormTolerance = v) },
        number("magDipTolerance", "mag_dip_tolerance_rad", "rad", G.REJECTION, "Dip angle tolerance", 0.01..0.7, { it.magDipTolerance }) { s, v -> s.copy(magDipTolerance = v) },
        number("magMaxRejectionTime", "mag_max_rejection_time_s", "s", G.REJECTION, "New field accepted after", 1.0..300.0, { it.magMaxRejectionTime }) { s, v -> s.copy(magMaxRejectionTime = v) },
        number("magReferenceTime", "mag_reference_time_s", "s", G.REJECTION, "Field reference follows over", 1.0..120.0, { it.magReferenceTime }) { s, v -> s.copy(magReferenceTime = v) },
        offable("magNewFieldTime", "mag_new_field_time_s", "s", G.REJECTION, "Steady new field trusted after", 0.0..60.0, { it.magNewFieldTime }, absent = 0.0) { s, v -> s.copy(magNewFieldTime = v) },
        offable("magNewFieldMinGyro", "mag_new_field_min_gyro_rad_s", "rad/s", G.REJECTION, "New field learnt while turning faster than", 0.0..2.0, { it.magNewFieldMinGyro }, absent = 0.0) { s, v -> s.copy(magNewFieldMinGyro = v) },
        offable("magResumeTime", "mag_resume_time_s", "s", G.REJECTION, "Heading gain back over", 0.0..60.0, { it.magResumeTime }, absent = 0.0) { s, v -> s.copy(magResumeTime = v) },
        offable("magRejectionFactor", "mag_rejection_factor", "", G.REJECTION, "Hold limited in time, paid back at", 0.0..10.0, { it.magRejectionFactor }, absent = 0.0) { s, v -> s.copy(magRejectionFactor = v) },
        offable("magFirstFieldTime", "mag_first_field_time_s", "s", G.REJECTION, "First reference after a steady field of", 0.0..60.0, { it.magFirstFieldTime }, absent = 0.0) { s, v -> s.copy(magFirstFieldTime = v) },
        offable("magUndisturbedTime", "mag_undisturbed_time_s", "s", G.REJECTION, "Disturbance ends after agreeing for", 0.0..10.0, { it.magUndisturbedTime }, absent = 0.0) { s, v -> s.copy(magUndisturbedTime = v) },
        offable("magTrustSpread", "mag_trust_spread", "", G.REJECTION, "Heading gain falls once the field wanders beyond", 0.0..0.2, { it.magTrustSpread }, absent = 0.0) { s, v -> s.copy(magTrustSpread = v) },
        number("magTrustTime", "mag_trust_time_s", "s", G.REJECTION, "Field wander measured over", 1.0..120.0, { it.magTrustTime }) { s, v -> s.copy(magTrustTime = v) },
        offable("hardIronThreshold", "hard_iron_threshold_ut", "µT", G.REJECTION, "Magnetometer offset taken off beyond", 0.0..20.0, { it.hardIronThreshold }, absent = 0.0) { s, v -> s.copy(hardIronThreshold = v) },
        offable("hardIronTime", "hard_iron_time_s", "s", G.REJECTION, "Magnetometer offset: older turns forgotten over", 0.0..3600.0, { it.hardIronTime }, absent = 0.0) { s, v -> s.copy(hardIronTime = v) },
        flag("accRejection", "acc_rejection", G.REJECTION, "Ignore the accelerometer in strong acceleration", { it.accRejection }) { s, v -> s.copy(accRejection = v) },
        number("accNormTolerance", "acc_norm_tolerance_m_s2", "m/s²", G.REJECTION, "Acceleration tolerance", 0.1..10.0, { it.accNormTolerance }) { s, v -> s.copy(accNormTolerance = v) },
        number("accAngleTolerance", "acc_angle_tolerance_rad", "rad", G.REJECTION, "Angle from up tolerance", 0.01..1.0, { it.accAngleTolerance }) { s, v -> s.copy(accAngleTolerance = v) },
        number("accMaxRejectionTime", "acc_max_rejection_time_s", "s", G.REJECTION, "Accelerometer trusted again after", 0.5..30.0, { it.accMaxRejectionTime }) { s, v -> s.copy(accMaxRejectionTime = v) },
        offable("inclinationRecoveryBeta", "inclination_recovery_beta", "rad/s", G.LOW_PASS, "Inclination recovery gain", 0.0..2.0, { it.inclinationRecoveryBeta }, absent = 0.0) { s, v -> s.copy(inclinationRecoveryBeta = v) },
        number("accTrustTime", "acc_trust_time_s", "s", G.LOW_PASS, "Recovery after a steady accelerometer of", 0.05..5.0, { it.accTrustTime }) { s, v -> s.copy(accTrustTime = v) },
        offable("recoveryAngle", "recovery_angle_rad", "rad", G.LOW_PASS, "Recovery when still and off by more than", 0.0..0.5, { it.recoveryAngle }, absent = 0.0) { s, v -> s.copy(recoveryAngle = v) },
        number("recoveryGyroThreshold", "recovery_gyro_threshold_rad_s", "rad/s", G.LOW_PASS, "Still for recovery below", 0.02..2.0, { it.recoveryGyroThreshold }) { s, v -> s.copy(recoveryGyroThreshold = v) },
        number("recoveryStillTime", "recovery_still_time_s", "s", G.LOW_PASS, "Still for recovery for", 0.0..2.0, { it.recoveryStillTime }) { s, v -> s.copy(recoveryStillTime = v) },
        offable("accLowPassTime", "acc_low_pass_time_s", "s", G.LOW_PASS, "Accelerometer low-pass time constant", 0.0..30.0, { it.accLowPassTime }, absent = 0.0) { s, v -> s.copy(accLowPassTime = v) },
        offable("gyroSaturation", "gyro_saturation_rad_s", "rad/s", G.SATURATION, "Gyroscope clipped at", 0.0..70.0, { it.gyroSaturation }, absent = 0.0) { s, v -> s.copy(gyroSaturation = v) },
        offable("headingGain", "heading_gain_1_s", "1/s", G.GAINS, "Heading correction gain", 0.0..0.5, { it.headingGain }, absent = 0.0) { s, v -> s.copy(headingGain = v) },
        offable("headingRecoveryTime", "heading_recovery_time_s", "s", G.GAINS, "Fast heading convergence for", 0.0..60.0, { it.headingRecoveryTime }, absent = 0.0) { s, v -> s.copy(headingRecoveryTime = v) },
        offable("motionBiasGain", "motion_bias_gain_rad_s2", "rad/s²", G.BIAS, "Bias estimation in motion, gain", 0.0..0.03, { it.motionBiasGain }, absent = 0.0) { s, v -> s.copy(motionBiasGain = v) },
        number("motionBiasRestTime", "motion_bias_rest_time_s", "s", G.BIAS, "Motion estimate ramps up after rest over", 0.0..1200.0, { it.motionBiasRestTime }) { s, v -> s.copy(motionBiasRestTime = v) },
        number("motionBiasLimit", "motion_bias_limit_rad_s", "rad/s", G.BIAS, "Bias limit per axis", 0.005..0.2, { it.motionBiasLimit }) { s, v -> s.copy(motionBiasLimit = v) },
        choice("outputFrame", "output_frame", G.GAINS, "Output earth frame", WorldFrame.entries.map { it.name }, { it.outputFrame.name }) { s, v -> s.copy(outputFrame = WorldFrame.valueOf(v)) },
        number("maxGap", "max_gap_s", "s", G.SATURATION, "Longest gap between samples", 0.05..2.0, { it.maxGap }) { s, v -> s.copy(maxGap = v) },
    )

    private val byName = all.associateBy { it.name }

    /** The setting called [name] (the property name), or null. */
    @JvmStatic
    public fun named(name: String): FilterSettingDescriptor? = byName[name]

    /**
     * [s] with the assignment "name=value" applied ("name=off" or "name=0" turns a mechanism off).
     * @throws IllegalArgumentException for a missing '=', an unknown name, or a value the settings reject.
     */
    @JvmStatic
    public fun apply(s: FilterSettings, assignment: String): FilterSettings {
        require('=' in assignment) { "expected name=value: $assignment" }
        val (name, value) = assignment.split('=', limit = 2)
        val d = named(name.trim()) ?: throw IllegalArgumentException("unknown setting $name (known: ${all.joinToString()})")
        return d.withText(s, value)
    }

    private fun number(
        name: String, key: String, unit: String, group: SettingGroup, title: String, range: ClosedFloatingPointRange<Double>,
        get: (FilterSettings) -> Double, absent: Double? = null, set: (FilterSettings, Double) -> FilterSettings,
    ) = FilterSettingDescriptor(name, key, unit, SettingKind.NUMBER, emptyList(), get, { s, v -> set(s, v as Double) }, absent, title, group, range, false)

    /** A mechanism's number that can be off: null in [FilterSettings], 0 or "off" in text. */
    private fun offable(
        name: String, key: String, unit: String, group: SettingGroup, title: String, range: ClosedFloatingPointRange<Double>,
        get: (FilterSettings) -> Double?, absent: Double? = null, set: (FilterSettings, Double?) -> FilterSettings,
    ) = FilterSettingDescriptor(name, key, unit, SettingKind.NUMBER, emptyList(), get, { s, v -> set(s, v as Double?) }, absent, title, group, range, true)

    private fun flag(name: String, key: String, group: SettingGroup, title: String, get: (FilterSettings) -> Boolean, set: (FilterSettings, Boolean) -> FilterSettings) =
        FilterSettingDescriptor(name, key, "", SettingKind.BOOLEAN, emptyList(), get, { s, v -> set(s, v as Boolean) }, null, title, group, null, false)

    private fun choice(name: String, key: String, group: SettingGroup, title: String, choices: List<String>, get: (FilterSettings) -> String, set: (FilterSettings, String) -> FilterSettings) =
        FilterSettingDescriptor(name, key, "", SettingKind.CHOICE, choices, get, { s, v -> set(s, v as String) }, null, title, group, null, false)
}
