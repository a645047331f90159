package dev.motionfusion.core.eval

import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.Paths

/**
 * VQF's figures on the data beside the repository, committed as src/test/resources/peers/vqf.csv
 * (input,metric,value,samples; made by fusion-bench/python/vqf_peers.py on the same rows the
 * project's filter steps on, scored by the project's metric code; see docs/ACCURACY.md "Peer
 * figures"). The tests compare the project with these, never with absolute bounds.
 */
internal object PeerFigures {
    /** How far behind VQF the project may be on a real export's tilt, degrees. */
    const val TILT_MARGIN_DEG = 0.5

    /** Benchmark RMSE may be at most this fraction above VQF's: none, the target is to be ahead (docs/ACCURACY.md, "Peer figures"). */
    const val RMSE_MARGIN = 0.0

    /** Fewer still samples than this are one short stillness, not a measure: reported, not compared. */
    const val MIN_STILL_SAMPLES = 30L

    /** The data folder (../shared/data or ../../shared/data), or null when absent. */
    val data: Path? = listOf(Paths.get("../shared/data"), Paths.get("../../shared/data")).firstOrNull { Files.isDirectory(it) }

    private val rows: List<List<String>> by lazy {
        val stream = PeerFigures::class.java.getResourceAsStream("/peers/vqf.csv") ?: error("no peers/vqf.csv among the test resources")
        stream.bufferedReader().readLines().filter { it.isNotBlank() && !it.startsWith("#") && !it.startsWith("input,") }.map { it.split(',') }
    }

    /** (input, metric) → value (NaN: "—", no sample), from the committed figures. */
    val vqf: Map<Pair<String, String>, Double> by lazy { rows.associate { (it[0] to it[1]) to (it[2].toDoubleOrNull() ?: Double.NaN) } }

    /** (input, metric) → the number of samples behind the figure (tilt figures only). */
    val samples: Map<Pair<String, String>, Long> by lazy { rows.filter { it[3].isNotEmpty() }.associate { (it[0] to it[1]) to it[3].toLong() } }

    /** VQF's figure for [input] and [metric]; a missing one fails the test that needs it. */
    fun of(input: String, metric: String): Double =
        vqf[input to metric] ?: throw AssertionError("no VQF figure for $input $metric in peers/vqf.csv: regenerate it (docs/ACCURACY.md, \"Peer figures\")")

    const val STILL_TILT = "still_tilt_median_deg"
    const val TOTAL_RMSE = "total_rmse_deg"
    const val OFFLINE_TOTAL_RMSE = "offline_total_rmse_deg"

    /** The after-motion metric's name for the window [fromS, toS). */
    fun afterMotion(fromS: Double, toS: Double) = "after_motion_tilt_median_deg_${fromS.toInt()}_${toS.toInt()}_s"

    /** A trial's group: "undisturbed" (names with undisturbed or NoDist) or "disturbed" (disturbed or Dist). */
    fun group(trial: String): String = when {
        trial.contains("undisturbed") || trial.contains("NoDist") -> "undisturbed"
        trial.contains("disturbed") || trial.contains("Dist") -> "disturbed"
        else -> throw AssertionError("trial $trial is in neither group (undisturbed/NoDist, disturbed/Dist)")
    }
}
