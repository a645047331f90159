/*
 * Command-line entry point: `Evaluate [--6d] [--report] [name=value ...] DIR...` prints BROAD's
 * metric for each trial under DIR as a Markdown table. name=value overrides a numeric or boolean
 * setting of FilterSettings (e.g. beta=0.02 accRejection=false); --report starts from the report's
 * own settings instead of the defaults.
 */
@file:JvmName("Evaluate")

package dev.motionfusion.core.eval

import dev.motionfusion.core.WorldFrame
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.Initialisation
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

/** Command-line overrides of [FilterSettings]: "name=value" by the name of a property. */
public object SettingsOverride {
    /**
     * [s] with the property named before '=' set to the value after it (numbers in SI units as the
     * property documents, booleans true/false, enums by name).
     * @throws IllegalArgumentException for an unknown name or a value the settings reject.
     */
    public fun apply(s: FilterSettings, assignment: String): FilterSettings {
        require('=' in assignment) { "expected name=value: $assignment" }
        val (name, value) = assignment.split('=', limit = 2)
        fun d() = value.toDouble()
        fun b() = value.toBooleanStrict()
        return when (name) {
            "mode" -> s.copy(mode = FilterMode.valueOf(value))
            "initialisation" -> s.copy(initialisation = Initialisation.valueOf(value))
            "outputFrame" -> s.copy(outputFrame = WorldFrame.valueOf(value))
            "beta" -> s.copy(beta = d())
            "zeta" -> s.copy(zeta = d())
            "restBiasEstimation" -> s.copy(restBiasEstimation = b())
            "restGyroThreshold" -> s.copy(restGyroThreshold = d())
            "restAccThreshold" -> s.copy(restAccThreshold = d())
            "restMinTime" -> s.copy(restMinTime = d())
            "restBiasTime" -> s.copy(restBiasTime = d())
            "magDisturbanceRejection" -> s.copy(magDisturbanceRejection = b())
            "magNormTolerance" -> s.copy(magNormTolerance = d())
            "magDipTolerance" -> s.copy(magDipTolerance = d())
            "magMaxRejectionTime" -> s.copy(magMaxRejectionTime = d())
            "magReferenceTime" -> s.copy(magReferenceTime = d())
            "accRejection" -> s.copy(accRejection = b())
            "accNormTolerance" -> s.copy(accNormTolerance = d())
            "accAngleTolerance" -> s.copy(accAngleTolerance = d())
            "accMaxRejectionTime" -> s.copy(accMaxRejectionTime = d())
            "maxGap" -> s.copy(maxGap = d())
            else -> throw IllegalArgumentException("unknown setting $name")
        }
    }
}
