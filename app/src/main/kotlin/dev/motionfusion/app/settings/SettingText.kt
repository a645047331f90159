package dev.motionfusion.app.settings

import android.content.Context
import dev.motionfusion.app.R
import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.app.sensor.label

/**
 * The words the screens show for a [Setting], from the resources of [Context]'s locale: its title
 * (`setting_<key>`), a switch's own line of help where it needs one (`setting_help_<key>`), the label of a choice (`setting_choice_<NAME>`, rates, durations, start delays and battery
 * levels formatted), and numbers in the locale's format. `SettingTextTest` checks every setting has
 * them in every shipped language.
 */
internal object SettingText {
    /** The resource package: the app's R, whatever the application id. */
    private val PACKAGE = R::class.java.name.substringBeforeLast('.')

    /** The string resource named [name], or 0. */
    private fun id(c: Context, name: String): Int = c.resources.getIdentifier(name, "string", PACKAGE)

    /** The title's resource of [s] (0 when missing: a defect the test finds). */
    fun titleRes(c: Context, s: Setting): Int = id(c, "setting_${s.key}")

    fun title(c: Context, s: Setting): String = titleRes(c, s).let { if (it == 0) s.title else c.getString(it) }

    /** A line of help of its own (`setting_help_<key>`, which then says the default too), or null: the row shows "Default …". */
    fun help(c: Context, s: Setting): String? = id(c, "setting_help_${s.key}").let { if (it == 0) null else c.getString(it) }

    /** The resource of choice [choice] of a setting whose choices are names (0 for rates, durations, levels). */
    fun choiceRes(c: Context, choice: String): Int = id(c, "setting_choice_$choice")

    /** The words shown for [choice] of [s]. */
    fun label(c: Context, s: Setting, choice: String): String = when (s.key) {
        Setting.RATE -> SamplingRate.parse(choice)?.label(c) ?: choice
        Setting.MAX_DURATION -> choice.toLongOrNull()?.let { duration(c, it) } ?: choice
        Setting.START_DELAY -> choice.toLongOrNull()?.let { if (it == 0L) c.getString(R.string.start_delay_off) else duration(c, it) } ?: choice
        Setting.STOP_BATTERY -> choice.toIntOrNull()?.let { if (it == 0) c.getString(R.string.battery_never) else c.getString(R.string.battery_percent, it) } ?: choice
        else -> choiceRes(c, choice).let { if (it == 0) choice else c.getString(it) }
    }

    /** 0 → "No limit", 900 → "15 min", 7200 → "2 h". */
    fun duration(c: Context, seconds: Long): String = when {
        seconds == 0L -> c.getString(R.string.duration_no_limit)
        seconds % 3600 == 0L -> c.getString(R.string.duration_hours, seconds / 3600)
        seconds % 60 == 0L -> c.getString(R.string.duration_minutes, seconds / 60)
        else -> c.getString(R.string.duration_seconds, seconds)
    }

}
