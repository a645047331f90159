package dev.motionfusion.app.settings

import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.settings.FilterSettingDescriptor
import dev.motionfusion.core.settings.FilterSettingDescriptors
import dev.motionfusion.core.settings.SettingGroup
import dev.motionfusion.core.settings.SettingKind

/**
 * The settings screen's sections, in the order shown; an empty one is not shown. [advanced]: the filter's tuning,
 * under "Advanced" (folded until opened).
 */
enum class Section(val advanced: Boolean = false) {
    RECORDING, HEADING, RECORDED_SENSORS, CALIBRATION, DISPLAY,
    GAINS(true), REJECTION(true), BIAS(true), LOW_PASS(true), SATURATION(true);

    companion object {
        fun of(group: SettingGroup): Section = when (group) {
            SettingGroup.GAINS -> GAINS
            SettingGroup.REJECTION -> REJECTION
            SettingGroup.BIAS -> BIAS
            SettingGroup.LOW_PASS -> LOW_PASS
            SettingGroup.SATURATION -> SATURATION
        }
    }
}

/**
 * One value of [LiveSettings] as the settings screen shows and [SettingsStore] keeps it: every
 * filter setting of fusion-core's table ([FilterSettingDescriptors], adapted by [of]) and the
 * app's own few ([APP]). Values are a Double, a Boolean or a choice's name, as the core table stores them
 * ([FilterSettingDescriptor.storedValue]: a mechanism that is off, null in FilterSettings, is 0 on its slider and in storage);
 * [with] validates through the settings' own types and throws IllegalArgumentException on a refused value.
 * [title] is the English name for messages; the screens show [SettingText]'s, from the resources.
 *
 * @property key the storage key (a filter setting's metadata member name).
 * @property range a number's slider ends, in [unit].
 * @property zeroDisables a number whose 0 means off: a switch beside its slider.
 */
class Setting(
    val key: String,
    val title: String,
    val section: Section,
    val kind: SettingKind,
    val unit: String = "",
    val choices: List<String> = emptyList(),
    val range: ClosedFloatingPointRange<Double>? = null,
    val zeroDisables: Boolean = false,
    private val read: (LiveSettings) -> Any,
    private val write: (LiveSettings, Any) -> LiveSettings,
) {
    fun value(s: LiveSettings): Any = read(s)

    /** [s] with this setting at [v]; IllegalArgumentException for a value of the wrong kind or one refused. */
    fun with(s: LiveSettings, v: Any): LiveSettings {
        val checked: Any = when (kind) {
            SettingKind.NUMBER -> (v as? Number)?.toDouble()?.takeIf { it.isFinite() } ?: throw IllegalArgumentException("$title: a number, got $v")
            SettingKind.BOOLEAN -> v as? Boolean ?: throw IllegalArgumentException("$title: on or off, got $v")
            SettingKind.CHOICE -> (v as? String)?.takeIf { it in choices || choiceIsValid(it) } ?: throw IllegalArgumentException("$title: one of ${choices.joinToString()}, got $v")
        }
        return write(s, checked)
    }

    /** [s] with this setting parsed from its stored [text]. */
    fun withText(s: LiveSettings, text: String): LiveSettings = with(
        s,
        when (kind) {
            SettingKind.NUMBER -> text.trim().toDoubleOrNull() ?: throw IllegalArgumentException("$title: a number, got '$text'")
            SettingKind.BOOLEAN -> text.trim().toBooleanStrictOrNull() ?: throw IllegalArgumentException("$title: true or false, got '$text'")
            SettingKind.CHOICE -> text.trim()
        },
    )

    /** The value as [SettingsStore] writes it and [withText] reads it back. */
    fun text(s: LiveSettings): String = value(s).toString()

    val default: Any get() = read(LiveSettings())

    /** The choices to offer with [s]: [choices], and the current one if it is none of them (a rate typed in another version). */
    fun choicesFor(s: LiveSettings): List<String> = value(s).toString().let { if (it in choices) choices else choices + it }

    /** A choice not offered but valid: a rate, a duration or a battery level kept by another version. */
    private fun choiceIsValid(c: String): Boolean = when (key) {
        RATE -> SamplingRate.parse(c) != null
        MAX_DURATION -> c.toLongOrNull()?.let { it in 0L..RecordingLimits.MAX_DURATION_LIMIT_S } == true
        STOP_BATTERY -> c.toIntOrNull()?.let { it in 0..RecordingLimits.MAX_STOP_BATTERY_PERCENT } == true
        else -> false
    }

    override fun toString(): String = key

    companion object {
        const val RATE = "rate"
        const val MAX_DURATION = "max_duration_s"
        const val STOP_BATTERY = "stop_battery_percent"
        const val START_DELAY = "start_delay_s"
        /** The "Walking through buildings" switch: the filter's magnetic trust on ([FilterSettings.BUILDINGS_TRUST_SPREAD]) or off. */
        const val BUILDINGS = "walking_through_buildings"
        /** An optional stream's switch: this and the stream's name in lower case ("record_rotation_vector"). */
        const val RECORD_PREFIX = "record_"

        /** A filter setting of fusion-core's table, as the screen shows it. */
        fun of(d: FilterSettingDescriptor): Setting = Setting(
            key = d.jsonKey, title = d.title, section = Section.of(d.group), kind = d.kind, unit = d.unit,
            choices = d.choices, range = d.range, zeroDisables = d.zeroDisables,
            read = { d.storedValue(it.filter) }, write = { s, v -> s.copy(filter = d.with(s.filter, v)) },
        )

        private val RATES = SamplingRate.Delay.entries.map { it.key } + listOf(25, 50, 100, 200, 400).map { SamplingRate.Hz(it).key }

        /**
         * The app's settings beside the filter's, one line each: a recording or calibration value
         * is added here (with its field in [LiveSettings]) and the screen and the store take it up.
         */
        val APP: List<Setting> = listOf(
            Setting(RATE, "Requested sensor rate", Section.RECORDING, SettingKind.CHOICE, choices = RATES,
                read = { it.rate.key }, write = { s, v -> s.copy(rate = requireNotNull(SamplingRate.parse(v as String)) { "no rate $v" }) }),
            Setting(START_DELAY, "Start recording after", Section.RECORDING, SettingKind.CHOICE, choices = LiveSettings.START_DELAY_CHOICES_S.map { it.toString() },
                read = { it.startDelayS.toString() }, write = { s, v -> s.copy(startDelayS = (v as String).toInt()) }),
            Setting(MAX_DURATION, "Stop recording after", Section.RECORDING, SettingKind.CHOICE, choices = RecordingLimits.DURATION_CHOICES_S.map { it.toString() },
                read = { it.limits.maxDurationS.toString() },
                write = { s, v -> s.copy(limits = s.limits.copy(maxDurationS = (v as String).toLong())) }),
            Setting(STOP_BATTERY, "Stop recording at battery", Section.RECORDING, SettingKind.CHOICE, choices = RecordingLimits.BATTERY_CHOICES.map { it.toString() },
                read = { it.limits.stopBatteryPercent.toString() },
                write = { s, v -> s.copy(limits = s.limits.copy(stopBatteryPercent = (v as String).toInt())) }),
            // A view of the filter's magTrustSpread (also under Advanced): on keeps a value set there, else takes the one for buildings.
            Setting(BUILDINGS, "Walking through buildings", Section.HEADING, SettingKind.BOOLEAN,
                read = { it.filter.magTrustSpread != null },
                write = { s, v -> s.copy(filter = s.filter.copy(magTrustSpread = if (v as Boolean) s.filter.magTrustSpread ?: FilterSettings.BUILDINGS_TRUST_SPREAD else null)) }),
        ) + LiveSettings.OPTIONAL_STREAMS.sortedBy { it.ordinal }.map { stream ->
            Setting(RECORD_PREFIX + stream.name.lowercase(), "Record ${stream.name.lowercase().replace('_', ' ')}", Section.RECORDED_SENSORS, SettingKind.BOOLEAN,
                read = { stream in it.optionalStreams },
                write = { s, v -> s.copy(optionalStreams = if (v as Boolean) s.optionalStreams + stream else s.optionalStreams - stream) })
        } + listOf(
            Setting("convention", "Angles shown", Section.DISPLAY, SettingKind.CHOICE, choices = AngleConvention.entries.map { it.name },
                read = { it.convention.name }, write = { s, v -> s.copy(convention = AngleConvention.valueOf(v as String)) }),
        )

        /**
         * Everything the screen shows, in order: the filter's table but its output frame (the app
         * shows and records device → ENU; LiveSettings requires it), then the app's.
         */
        val ALL: List<Setting> = FilterSettingDescriptors.all.filter { it.name != "outputFrame" }.map(::of) + APP
    }
}
