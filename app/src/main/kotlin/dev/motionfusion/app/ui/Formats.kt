package dev.motionfusion.app.ui

import android.content.Context
import java.math.RoundingMode
import java.text.NumberFormat
import java.util.Locale

/** Numbers as the user's language writes them (decimal comma in German). */
internal object Formats {
    /** The locale the resources of [c] are in (that of its configuration, which getString formats with). */
    fun locale(c: Context): Locale = c.resources.configuration.locales[0] ?: Locale.getDefault()

    /** [v] with at most [decimals] decimals, trailing zeros dropped, in the locale's digits and decimal mark. */
    fun number(c: Context, v: Double, decimals: Int): String = NumberFormat.getNumberInstance(locale(c)).apply {
        maximumFractionDigits = decimals
        minimumFractionDigits = 0
        isGroupingUsed = false
        roundingMode = RoundingMode.HALF_EVEN
    }.format(v)

    /** A gap between a recording's parts, "0:42" (unknown: "—"). */
    fun gap(gapNs: Long?): String = gapNs?.let { android.text.format.DateUtils.formatElapsedTime((it / 1_000_000_000L).coerceAtLeast(0)) } ?: "—"
}
