package dev.motionfusion.core.eval

import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.io.Json
import dev.motionfusion.core.filter.offline.OfflineSettings
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
    const val TOTAL_RMSE_6D = "total_rmse_6d_deg"

    /** The after-motion metric's name for the window [fromS, toS). */
    fun afterMotion(fromS: Double, toS: Double) = "after_motion_tilt_median_deg_${fromS.toInt()}_${toS.toInt()}_s"

    /** The group name that stands for all of a subset's trials. */
    const val OVERALL = "overall"

    /**
     * How a subset's trials fall into groups: [of] a trial's meta.json gives its group (null: none of [groups]),
     * [groups] in the order the subset's README lists them; [trials] is how many trial folders the subset has.
     */
    class Grouping(val trials: Int, val groups: List<String>, val of: (meta: Map<*, *>) -> String?)

    /** The evaluation subsets beside the repository and how each is grouped, as its README groups it. */
    val subsets: Map<String, Grouping> = linkedMapOf(
        // BROAD: meta.json "groups" holds undisturbed or disturbed.
        "broad-subset" to Grouping(7, listOf("undisturbed", "disturbed")) { m ->
            (m["groups"] as? List<*>)?.let { g -> if ("undisturbed" in g) "undisturbed" else if ("disturbed" in g) "disturbed" else null }
        },
        // Tyrex: meta.json "disturbed" (the NoDist/Dist of the names).
        "tyrex-subset" to Grouping(14, listOf("undisturbed", "disturbed")) { m -> (m["disturbed"] as? Boolean)?.let { if (it) "disturbed" else "undisturbed" } },
        // OxIOD: meta.json "motion", the placement (stated by OxIOD or inferred from the recording).
        "oxiod-subset" to Grouping(33, listOf("hand", "pocket", "handbag", "running")) { m ->
            when (m["motion"]) {
                "handheld" -> "hand"
                "pocket" -> "pocket"
                "handbag" -> "handbag"
                "running" -> "running"
                else -> null
            }
        },
        // ADVIO: meta.json "venue".
        "advio-subset" to Grouping(11, listOf("mall", "metro", "office", "outdoor")) { m -> (m["venue"] as? String)?.takeIf { it in listOf("mall", "metro", "office", "outdoor") } },
    )

    private fun grouping(subset: String): Grouping = subsets[subset] ?: throw AssertionError("$subset is not an evaluation subset (${subsets.keys})")

    /** A trial's meta.json (an empty map without one). */
    private fun meta(subset: String, trial: String): Map<*, *> {
        val f = data!!.resolve(subset).resolve(trial).resolve("meta.json")
        if (!Files.exists(f)) return emptyMap<String, Any>()
        return Json.parse(String(Files.readAllBytes(f), Charsets.UTF_8), f.toString()) as? Map<*, *> ?: throw AssertionError("$f: not a JSON object")
    }

    private val groupOf = java.util.concurrent.ConcurrentHashMap<Pair<String, String>, String>()

    /**
     * [trial]'s group within [subset], from the field of its meta.json that [subsets] names for the subset (BROAD
     * "groups", Tyrex "disturbed", OxIOD "motion", ADVIO "venue"). The one grouping every test uses; needs the data.
     */
    fun group(subset: String, trial: String): String = groupOf.getOrPut(subset to trial) {
        grouping(subset).of(meta(subset, trial)) ?: throw AssertionError("$subset/$trial: its meta.json puts it in none of ${grouping(subset).groups}")
    }

    /**
     * True when [subset]/[trial] is scored, for every method, with one constant heading offset removed (the 6d score
     * of `fusion eval --6d`): its meta.json declares `"scoring": "6d: ..."` (ADVIO: the truth has no north). Its
     * committed VQF figures are scored so, and so must be the project's ([evaluate]).
     */
    fun headingOffsetRemoved(subset: String, trial: String): Boolean = (meta(subset, trial)["scoring"] as? String)?.startsWith("6d") == true

    /** The trial folders of [subset] (all, or those of [group]), in name order; needs the data. */
    fun trials(subset: String, group: String = OVERALL): List<String> {
        val names = Evaluation.findTrials(listOf(data!!.resolve(subset).toFile())).map { it.name }
        return if (group == OVERALL) names else names.filter { group(subset, it) == group }
    }

    /**
     * The project's scores on every trial of [subset] with [settings] (offline with [offline]), scored as the subset
     * declares: with the heading offset removed where [headingOffsetRemoved] (and for a 6D filter), else as is.
     */
    fun evaluate(subset: String, settings: FilterSettings, offline: OfflineSettings? = null): List<TrialResult> =
        Evaluation.findTrials(listOf(data!!.resolve(subset).toFile())).map { dir ->
            val trial = Trial.load(dir)
            if (!headingOffsetRemoved(subset, dir.name)) {
                Evaluation.evaluate(trial, settings, offline)
            } else {
                TrialResult(trial.name, BroadMetric.streamed(true) { add -> if (offline == null) Evaluation.run(trial, settings, add) else Evaluation.runOffline(trial, settings, offline, add) })
            }
        }

    /**
     * VQF on a group of a subset: the means over its [trials] of the committed per-trial total RMSE of VQF 9D
     * ([nineD], real-time), VQF 6D ([sixD], no magnetometer, heading offset removed) and vqf.offlineVQF 9D
     * ([offline]), degrees; NaN where the figures hold none for the subset.
     */
    data class VqfMeans(val subset: String, val group: String, val trials: Int, val nineD: Double, val sixD: Double, val offline: Double)

    /** [VqfMeans] of [subset]'s [group] ([OVERALL]: all its trials); a trial without a 9D or offline figure fails; needs the data. */
    fun vqfMeans(subset: String, group: String = OVERALL): VqfMeans {
        val names = trials(subset, group)
        if (names.isEmpty()) throw AssertionError("no $group trial in $subset")
        fun mean(metric: String) = names.map { of("$subset/$it", metric) }.average()
        val sixD = if (names.all { vqf.containsKey("$subset/$it" to TOTAL_RMSE_6D) }) mean(TOTAL_RMSE_6D) else Double.NaN
        return VqfMeans(subset, group, names.size, mean(TOTAL_RMSE), sixD, mean(OFFLINE_TOTAL_RMSE))
    }
}
