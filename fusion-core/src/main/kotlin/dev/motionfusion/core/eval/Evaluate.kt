/*
 * Command-line entry point: `Evaluate [--6d] [--report] [name=value ...] DIR...` prints BROAD's
 * metric for each trial under DIR as a Markdown table. name=value overrides a numeric or boolean
 * setting of FilterSettings (e.g. beta=0.02 accRejection=false); --report starts from the report's
 * own settings instead of the defaults.
 */
@file:JvmName("Evaluate")

package dev.motionfusion.core.eval

import dev.motionfusion.core.filter.FilterSettingDescriptors
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.io.DataFormatException
import java.io.File
import kotlin.system.exitProcess

public fun main(args: Array<String>) {
    var settings = FilterSettings()
    val dirs = ArrayList<File>()
    val overrides = ArrayList<String>()
    for (a in args) {
        when {
            a == "--report" -> settings = FilterSettings.report()
            a == "--6d" -> overrides.add("mode=IMU")
            a.contains('=') -> overrides.add(a)
            a.startsWith("-") -> usage("unknown option $a")
            else -> dirs.add(File(a))
        }
    }
    if (dirs.isEmpty()) usage("no trial folder given")
    try {
        settings = overrides.fold(settings) { s, o -> SettingsOverride.apply(s, o) }
        val results = Evaluation.evaluateAll(dirs, settings)
        println(settings)
        print(Evaluation.table(results))
    } catch (e: DataFormatException) {
        System.err.println(e.message)
        exitProcess(1)
    } catch (e: IllegalArgumentException) {
        usage(e.message ?: e.toString())
    }
}

private fun usage(message: String): Nothing {
    System.err.println("$message\nusage: Evaluate [--6d] [--report] [setting=value ...] TRIAL_DIR|DATASET_DIR ...")
    exitProcess(2)
}

/** Command-line overrides of [FilterSettings]: "name=value" by the name of a property ([FilterSettingDescriptors]). */
public object SettingsOverride {
    /**
     * [s] with the property named before '=' set to the value after it (numbers in SI units as the
     * property documents, booleans true/false, enums by name).
     * @throws IllegalArgumentException for an unknown name or a value the settings reject.
     */
    public fun apply(s: FilterSettings, assignment: String): FilterSettings = FilterSettingDescriptors.apply(s, assignment)
}
