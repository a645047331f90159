package dev.motionfusion.cli

import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.settings.FilterSettingDescriptor
import dev.motionfusion.core.settings.FilterSettingDescriptors
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.Initialisation
import dev.motionfusion.core.settings.SettingKind
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.filter.offline.OfflineSettings
import java.io.PrintStream

/** The filter settings options shared by replay, eval, compare and plot. */
internal object FilterOptions {
    val VALUED = setOf("--beta", "--zeta", "--mode", "--init", "--max-gap", "--set", "--offline-weight", "--offline-smoothing")
    val FLAGS = setOf("--report", "--default-settings", "--no-rest-bias", "--no-mag-rejection", "--acc-rejection", "--offline")

    val HELP = """
        |Filter settings (defaults: FilterSettings(), chosen leaving one data set out of four (docs/ACCURACY.md);
        |a session whose meta.json records the live filter's settings starts from those instead, so
        |its replay reproduces orientation.csv; a note says so; the options below change them):
        |  --default-settings   start from FilterSettings() even for such a session
        |  --mode 6d|9d         6d: gyroscope + accelerometer; 9d: + magnetometer (default 9d;
        |                       6d for a recording without a magnetometer, with a note)
        |  --beta B             gradient step gain β, rad/s (default ${FilterSettings().beta})
        |  --zeta Z             gyroscope bias drift gain ζ, rad/s² (default off; 0 is off)
        |  --init identity|first-sample   start at the identity or from the first readings
        |  --no-rest-bias       do not estimate the gyroscope bias at rest
        |  --no-mag-rejection   no magnetic disturbance rejection (off by default; on in --report and
        |                       in some recorded settings: --set magDisturbanceRejection=true turns it on)
        |  --acc-rejection      skip the accelerometer during strong linear acceleration
        |  --max-gap S          longest accepted gap between samples, s (default 0.5)
        |  --report             start from the Madgwick report's own settings instead
        |  --set NAME=VALUE     any FilterSettings property by name, e.g. --set magNormTolerance=0.15
        |                       (several: --set restMinTime=1,restBiasTime=3, or --set once for each);
        |                       on a walk through buildings, --set magTrustSpread=0.005 holds heading
        |                       where the field wanders (docs/ACCURACY.md, "Walks through buildings");
        |                       NAME=off (or 0) turns off a mechanism marked "or off"; names, units, defaults:
        |${settingsTable()}
        |  --offline            the offline estimate: each orientation from the whole recording, the
        |                       samples after it as well as before (a forward and a backward pass
        |                       with these settings, combined, the heading then turned towards a
        |                       smoother's that pins it at rests and takes the gyroscope's drift
        |                       out between them; docs/ACCURACY.md, "Offline"); the same rows and
        |                       columns; needs a temporary file of ${OfflineSettings.SPILL_BYTES_PER_ROW} bytes per row
        |                       (java.io.tmpdir), removed however the run ends
        |  --offline-weight W   the backward pass's weight in the combination, 0…1, in heading (where
        |                       neither pass met a disturbed field lately) and inclination alike
        |                       (default ${OfflineSettings().backwardWeight} in heading, ${OfflineSettings().inclinationBackwardWeight} in inclination)
        |  --offline-smoothing W  how far the heading is turned towards the smoother's, 0…1
        |                       (default ${OfflineSettings().headingSmoothing}; 0: without the smoother)
        |""".trimMargin()

    /** The offline settings (--offline, --offline-weight, --offline-smoothing), or null for the causal filter. */
    fun offline(o: Options): OfflineSettings? {
        val w = o.double("--offline-weight")
        val smoothing = o.double("--offline-smoothing")
        if (!o.has("--offline")) {
            if (w != null) throw UsageException("--offline-weight needs --offline")
            if (smoothing != null) throw UsageException("--offline-smoothing needs --offline")
            return null
        }
        var s = OfflineSettings()
        try {
            if (w != null) s = s.copy(backwardWeight = w, inclinationBackwardWeight = w)
        } catch (e: IllegalArgumentException) {
            throw UsageException("--offline-weight: ${e.message}")
        }
        try {
            if (smoothing != null) s = s.copy(headingSmoothing = smoothing)
        } catch (e: IllegalArgumentException) {
            throw UsageException("--offline-smoothing: ${e.message}")
        }
        return s
    }

    /** One line per setting of [FilterSettingDescriptors]: name, unit, default, and whether it can be off. */
    private fun settingsTable(): String {
        val d = FilterSettings()
        return FilterSettingDescriptors.all.joinToString("\n") { s ->
            val unit = if (s.unit.isEmpty()) "" else " ${s.unit}"
            val choices = if (s.kind == SettingKind.CHOICE) " (${s.choices.joinToString("|")})" else ""
            val value = s.value(d)?.let { "$it$unit" } ?: "${FilterSettingDescriptor.OFF}${if (unit.isEmpty()) "" else " (${s.unit})"}"
            val off = if (s.zeroDisables && s.value(d) != null) " or off" else ""
            "|                         ${s.name} = $value$choices$off"
        }
    }

    /**
     * The settings for [rec]: the options applied to the live filter's recorded settings when its
     * meta.json has them (a note on [err] unless --quiet), else to the defaults. A recording without a
     * magnetometer runs in 6D (IMU mode; a note unless --quiet): in 9D the filter would wait maxGap for
     * a field before starting, and the output would claim a magnetic heading it has not.
     */
    fun settings(o: Options, rec: Recording, err: PrintStream, command: String): FilterSettings {
        val recorded = rec.metadata?.filterSettings?.takeUnless { o.has("--report") || o.has("--default-settings") }
        if (recorded != null && !o.has("--quiet")) {
            err.println("fusion $command: note: ${rec.name}: starting from the live filter's settings in meta.json (--default-settings for the defaults)")
        }
        val s = settings(o, recorded)
        if (s.mode != FilterMode.MARG || rec.hasMagnetometer) return s
        if (!o.has("--quiet")) {
            err.println("fusion $command: note: ${rec.name}: no magnetometer: 6D (the heading is the gyroscope's alone, its zero the start's)")
        }
        return s.copy(mode = FilterMode.IMU)
    }

    /** The options applied to [base], or to the defaults (FilterSettings.report() with --report). */
    fun settings(o: Options, base: FilterSettings? = null): FilterSettings {
        var s = base ?: if (o.has("--report")) FilterSettings.report() else FilterSettings()
        try {
            o.value("--mode")?.let {
                s = s.copy(mode = when (it.lowercase()) {
                    "6d", "imu" -> FilterMode.IMU
                    "9d", "marg" -> FilterMode.MARG
                    else -> throw UsageException("--mode expects 6d or 9d, got '$it'")
                })
            }
            o.double("--beta")?.let { s = number(s, "--beta", "beta", it) }
            o.double("--zeta")?.let { s = number(s, "--zeta", "zeta", it) }
            o.double("--max-gap")?.let { s = number(s, "--max-gap", "maxGap", it) }
            o.value("--init")?.let {
                s = s.copy(initialisation = when (it.lowercase()) {
                    "identity" -> Initialisation.IDENTITY
                    "first-sample" -> Initialisation.FIRST_SAMPLE
                    else -> throw UsageException("--init expects identity or first-sample, got '$it'")
                })
            }
            if (o.has("--no-rest-bias")) s = s.copy(restBiasEstimation = false)
            if (o.has("--no-mag-rejection")) s = s.copy(magDisturbanceRejection = false)
            if (o.has("--acc-rejection")) s = s.copy(accRejection = true)
            // Each setting once: a second value for it, by --set or by its own option, would silently replace the first.
            val given = HashMap<String, String>()
            for ((option, name) in OWN_OPTIONS) if (o.has(option) || o.value(option) != null) given[name] = option
            o.values("--set").flatMap { it.split(',') }.filter { it.isNotBlank() }.forEach { a ->
                if ('=' !in a) throw UsageException("--set expects NAME=VALUE, got '$a'")
                val name = a.substringBefore('=').trim()
                given.put(name, "--set $name")?.let { earlier -> throw UsageException("--set $name: $name is already given by $earlier; give it once") }
                s = applySet(s, a.trim())
            }
        } catch (e: IllegalArgumentException) {
            throw UsageException(e.message ?: "invalid filter setting")
        }
        return s
    }

    /** The options that set one FilterSettings property each, and that property. */
    private val OWN_OPTIONS = listOf(
        "--mode" to "mode", "--beta" to "beta", "--zeta" to "zeta", "--max-gap" to "maxGap", "--init" to "initialisation",
        "--no-rest-bias" to "restBiasEstimation", "--no-mag-rejection" to "magDisturbanceRejection", "--acc-rejection" to "accRejection",
    )

    /** [s] with the number setting [name] (option [option]) set through its descriptor, so its limits apply. */
    private fun number(s: FilterSettings, option: String, name: String, v: Double): FilterSettings = try {
        FilterSettingDescriptors.named(name)!!.with(s, v)
    } catch (e: IllegalArgumentException) {
        throw UsageException("$option: ${e.message}")
    }

    /** One --set NAME=VALUE, with its errors in this tool's words. */
    private fun applySet(s: FilterSettings, assignment: String): FilterSettings {
        val name = assignment.substringBefore('=').trim()
        val value = assignment.substringAfter('=').trim()
        val d = FilterSettingDescriptors.named(name)
            ?: throw UsageException("--set $name: no such setting (names as in FilterSettings, e.g. beta, magNormTolerance; see --help)")
        val malformed = when (d.kind) {
            SettingKind.NUMBER -> when {
                value.toDoubleOrNull() != null -> null
                d.zeroDisables -> if (value.equals(FilterSettingDescriptor.OFF, ignoreCase = true)) null else "'$value' is not a number or off"
                else -> "'$value' is not a number"
            }
            SettingKind.BOOLEAN -> if (value.toBooleanStrictOrNull() == null) "'$value' is not true or false" else null
            SettingKind.CHOICE -> if (value !in d.choices) "'$value' is not one of ${d.choices.joinToString(", ")}" else null
        }
        if (malformed != null) throw UsageException("--set $name: $malformed")
        return try {
            d.withText(s, value)
        } catch (e: IllegalArgumentException) {
            throw UsageException("--set $name: ${e.message ?: "invalid value '$value'"}")
        }
    }
}
