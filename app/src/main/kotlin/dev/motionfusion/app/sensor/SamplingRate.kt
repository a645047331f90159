package dev.motionfusion.app.sensor

import android.content.Context
import dev.motionfusion.app.R

/**
 * The rate requested from Android for each sensor: one of Android's delays or a rate in Hz.
 * A request is a hint: devices deliver faster or slower, in quantised steps, and Android 12+
 * caps motion sensors at 200 Hz unless HIGH_SAMPLING_RATE_SENSORS is declared (it is).
 */
sealed interface SamplingRate {
    /** The argument for `SensorManager.registerListener`: a SENSOR_DELAY_* constant or a period in µs. */
    val registerArgument: Int

    /** The nominal period, µs (0 for "as fast as possible"). */
    val nominalPeriodUs: Int

    /** A stable text for storage ("fastest", "game", "ui", "normal" or "hz:123"); the screens' words are [label]'s. */
    val key: String

    /** Android's named delays with their SENSOR_DELAY_* constants and nominal periods. */
    enum class Delay(override val registerArgument: Int, override val nominalPeriodUs: Int, override val key: String) : SamplingRate {
        FASTEST(0, 0, "fastest"),
        GAME(1, 20_000, "game"),
        UI(2, 66_667, "ui"),
        NORMAL(3, 200_000, "normal"),
    }

    /** A rate in Hz, [MIN_HZ]..[MAX_HZ], requested as the period 10⁶/hz µs. */
    data class Hz(val hz: Int) : SamplingRate {
        init {
            require(hz in MIN_HZ..MAX_HZ) { "rate must be $MIN_HZ..$MAX_HZ Hz, got $hz" }
        }

        override val registerArgument: Int get() = 1_000_000 / hz
        override val nominalPeriodUs: Int get() = 1_000_000 / hz
        override val key: String get() = "hz:$hz"
    }

    companion object {
        const val MIN_HZ = 1
        const val MAX_HZ = 1000

        /** The rate stored under [key], or null when [key] is not one [SamplingRate.key] produces. */
        fun parse(key: String): SamplingRate? {
            Delay.entries.firstOrNull { it.key == key }?.let { return it }
            if (!key.startsWith("hz:")) return null
            val hz = key.removePrefix("hz:").toIntOrNull() ?: return null
            return if (hz in MIN_HZ..MAX_HZ) Hz(hz) else null
        }
    }
}

/** What the screens call [this] in the language of [c]: "Game (50 Hz)", "100 Hz". */
fun SamplingRate.label(c: Context): String = when (this) {
    SamplingRate.Delay.FASTEST -> c.getString(R.string.rate_fastest)
    SamplingRate.Delay.GAME -> c.getString(R.string.rate_game)
    SamplingRate.Delay.UI -> c.getString(R.string.rate_ui)
    SamplingRate.Delay.NORMAL -> c.getString(R.string.rate_normal)
    is SamplingRate.Hz -> c.getString(R.string.rate_hz_label, hz)
}
