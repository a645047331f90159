package dev.motionfusion.core.eval

import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.offline.OfflineSettings
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.DynamicTest
import org.junit.jupiter.api.TestFactory
import java.nio.file.Files
import java.util.Locale
import kotlin.math.abs

/**
 * The default settings against VQF on the evaluation subsets beside the repository
 * (../shared/data; never copied into it): on each of BROAD, Tyrex, OxIOD and ADVIO, overall and in each group
 * (undisturbed, disturbed; in the hand, pocket, handbag, running; mall, metro, office, outdoor), the project's mean
 * total RMSE (BROAD's metric; ADVIO with the heading offset removed, as its README scores) is at most
 * [PeerFigures.RMSE_MARGIN] (0: the target is to be ahead) above VQF's on the same trials, VQF's figures being
 * those committed in peers/vqf.csv ([PeerFigures]): the causal replay against VQF's real-time
 * filter, the offline replay (default [OfflineSettings]) against `vqf.offlineVQF`. Where the project is still
 * behind ([BEHIND]: ADVIO's metro station causal, a single walk among trains; docs/ACCURACY.md), the group's
 * measured figure is asserted instead, with [BEHIND_MARGIN], so that a regression fails there too. The committed
 * VQF figures are checked against the READMEs. Groups come from each trial's meta.json ([PeerFigures.group]).
 * Skipped when the data is absent; a trial missing from the data or from the figures fails.
 */
class SubsetAccuracyTest {
    /** The subsets the project is compared with VQF on. */
    private val compared = listOf("broad-subset", "tyrex-subset", "oxiod-subset", "advio-subset")

    /** The subsets the offline estimate's gain over the causal one is checked on. */
    private val offlineGain = compared

    private fun results(offline: OfflineSettings?): Map<String, List<TrialResult>> =
        compared.associateWith { name ->
            PeerFigures.evaluate(name, FilterSettings(), offline).also {
                assertEquals(PeerFigures.subsets.getValue(name).trials, it.size, "trials in $name")
            }
        }

    private val causal by lazy { results(null) }
    private val offline by lazy { results(OfflineSettings()) }

    @TestFactory
    fun `defaults ahead of VQF on each subset overall and in each group`(): List<DynamicTest> =
        compare("causal", PeerFigures.TOTAL_RMSE) { causal }

    /**
     * The committed VQF figures are VQF's total RMSE: they agree with the VQF rows the subsets' publishers give in
     * their READMEs (VQF 9D; VQF offline 9D and VQF 6D where given), per trial (BROAD) or overall and per group in
     * the README's column order (Tyrex, OxIOD, ADVIO; each column's trial count is checked against the groups the
     * trials' meta.json give). Figures read from the wrong column (heading instead of total, as once happened), a
     * trial put in the wrong group, or a subset scored otherwise than its README says (ADVIO: heading offset
     * removed) fail here.
     */
    @TestFactory
    fun `committed VQF figures agree with the subsets' published VQF row`(): List<DynamicTest> =
        PeerFigures.subsets.keys.map { subset ->
            DynamicTest.dynamicTest("published VQF $subset") {
                assumeTrue(PeerFigures.data != null, "no ../shared/data beside the repository: not compared")
                val lines = Files.readAllLines(PeerFigures.data!!.resolve(subset).resolve("README.md"))
                val trials = PeerFigures.trials(subset)
                val failures = mutableListOf<String>()
                val rows = PUBLISHED_ROWS.filter { (prefix, _) -> lines.any { it.startsWith(prefix) } }
                assertTrue(rows.any { it.second == PeerFigures.TOTAL_RMSE }, "$subset's README has no VQF 9D row")
                for ((prefix, metric) in rows) {
                    val i = lines.indexOfFirst { it.startsWith(prefix) }
                    val published = cells(lines[i]).drop(1).map { firstNumber(it) ?: throw AssertionError("$subset README, ${prefix.removePrefix("| ")} row: '$it' is not a figure") }
                    val header = cells(lines.subList(0, i).last { it.startsWith("| method") }).drop(1)
                    assertEquals(header.size, published.size, "$subset README: figures in the ${prefix.removePrefix("| ")} row against its table's columns")
                    fun committed(names: List<String>) = names.map { PeerFigures.of("$subset/$it", metric) }.average()
                    // BROAD's rows: one figure per trial in folder order, then the mean; the others: all, then each group.
                    val expected: List<Pair<String, List<String>>> = if (published.size == trials.size + 1) {
                        trials.map { it to listOf(it) } + (PeerFigures.OVERALL to trials)
                    } else {
                        val groups = listOf(PeerFigures.OVERALL) + PeerFigures.subsets.getValue(subset).groups
                        assertEquals(groups.size, published.size, "$subset README: columns of the ${prefix.removePrefix("| ")} row against the groups $groups")
                        groups.mapIndexed { c, g ->
                            val names = PeerFigures.trials(subset, g)
                            assertEquals(firstNumber(header[c])?.toInt(), names.size, "$subset README column '${header[c]}': trials in group $g by meta.json")
                            g to names
                        }
                    }
                    expected.forEachIndexed { c, (what, names) ->
                        val ours = committed(names)
                        if (abs(ours - published[c]) > PUBLISHED_TOLERANCE_DEG) {
                            failures += String.format(Locale.ROOT, "%s %s (%d trials), %s: committed %.3f°, README %.2f°", subset, what, names.size, metric, ours, published[c])
                        }
                    }
                }
                assertTrue(failures.isEmpty(), "committed VQF figures against the README:\n" + failures.joinToString("\n"))
            }
        }

    /** Every trial of every subset has its three committed VQF figures, and [PeerFigures.vqfMeans] gives them per group. */
    @TestFactory
    fun `VQF means per subset and group`(): List<DynamicTest> =
        PeerFigures.subsets.map { (subset, grouping) ->
            DynamicTest.dynamicTest("VQF means $subset") {
                assumeTrue(PeerFigures.data != null, "no ../shared/data beside the repository: not evaluated")
                assertEquals(grouping.trials, PeerFigures.trials(subset).size, "trials in $subset")
                val means = (listOf(PeerFigures.OVERALL) + grouping.groups).map { PeerFigures.vqfMeans(subset, it) }
                assertEquals(grouping.trials, means.drop(1).sumOf { it.trials }, "$subset: every trial in exactly one group")
                for (m in means) {
                    println(String.format(Locale.ROOT, "VQF %s %s (%d trials): 9D %.2f°, 6D %.2f°, offline %.2f°", subset, m.group, m.trials, m.nineD, m.sixD, m.offline))
                    assertTrue(m.nineD.isFinite() && m.sixD.isFinite() && m.offline.isFinite(), "$m: a figure missing")
                }
            }
        }

    @TestFactory
    fun `offline defaults ahead of VQF offline on each subset overall and in each group`(): List<DynamicTest> =
        compare("offline", PeerFigures.OFFLINE_TOTAL_RMSE) { offline }

    /** The offline estimate's other target: at least 15 % below the causal defaults on the same trials, overall and in each group. */
    @TestFactory
    fun `offline defaults at least 15 percent below the causal defaults on each subset overall and in each group`(): List<DynamicTest> =
        groups(offlineGain).map { (subset, group) ->
            DynamicTest.dynamicTest("offline against causal $subset $group") {
                assumeTrue(PeerFigures.data != null, "no ../shared/data beside the repository: not evaluated")
                fun mean(r: Map<String, List<TrialResult>>): Double {
                    val trials = r.getValue(subset).filter { group == PeerFigures.OVERALL || PeerFigures.group(subset, it.trial) == group }
                    assertTrue(trials.isNotEmpty(), "no $group trial in $subset")
                    return trials.map { it.error.totalDeg }.average()
                }
                val before = mean(causal)
                val after = mean(offline)
                val msg = String.format(Locale.ROOT, "%s %s: offline %.2f°, causal %.2f° (%+.0f %%)", subset, group, after, before, 100 * (after - before) / before)
                println(msg)
                assertTrue(after <= 0.85 * before, msg)
            }
        }

    /** The magnetic trust at the value for walks through buildings (FilterSettings.magTrustSpread; off by default). */
    private val indoor = FilterSettings(magTrustSpread = FilterSettings.BUILDINGS_TRUST_SPREAD)

    /**
     * On ADVIO's walks, the magnetic trust at its value for walks through buildings: in every venue (outdoors
     * too) ahead of VQF 9D and within [INDOOR_OF_BEST] of the better of VQF 9D and VQF 6D there; overall ahead
     * of VQF 6D; the offline estimate ahead of VQF offline overall and in every venue.
     */
    @TestFactory
    fun `the magnetic trust on ADVIO's walks through buildings`(): List<DynamicTest> {
        val causalRuns by lazy { PeerFigures.evaluate("advio-subset", indoor) }
        val offlineRuns by lazy { PeerFigures.evaluate("advio-subset", indoor, OfflineSettings()) }
        fun mean(runs: List<TrialResult>, group: String) =
            runs.filter { group == PeerFigures.OVERALL || PeerFigures.group("advio-subset", it.trial) == group }.map { it.error.totalDeg }.average()
        return (listOf(PeerFigures.OVERALL) + PeerFigures.subsets.getValue("advio-subset").groups).map { group ->
            DynamicTest.dynamicTest("magnetic trust advio-subset $group") {
                assumeTrue(PeerFigures.data != null, "no ../shared/data beside the repository: not evaluated")
                val vqf = PeerFigures.vqfMeans("advio-subset", group)
                val ours = mean(causalRuns, group)
                val msg = String.format(Locale.ROOT, "magnetic trust advio-subset %s: %.2f° (VQF 9D %.2f°, 6D %.2f°, offline %.2f°)", group, ours, vqf.nineD, vqf.sixD, vqf.offline)
                println(msg)
                when (group) {
                    PeerFigures.OVERALL -> {
                        assertTrue(ours <= vqf.sixD, msg)
                        val off = mean(offlineRuns, group)
                        println(String.format(Locale.ROOT, "magnetic trust advio-subset offline: %.2f° (VQF offline %.2f°)", off, vqf.offline))
                        assertTrue(off <= vqf.offline, "offline $off°, VQF offline ${vqf.offline}°")
                    }
                    else -> {
                        val off = mean(offlineRuns, group)
                        println(String.format(Locale.ROOT, "magnetic trust advio-subset %s offline: %.2f° (VQF offline %.2f°)", group, off, vqf.offline))
                        assertTrue(off <= vqf.offline, "offline $off°, VQF offline ${vqf.offline}°")
                        assertTrue(ours <= vqf.nineD, msg)
                        assertTrue(ours <= minOf(vqf.nineD, vqf.sixD) * (1 + INDOOR_OF_BEST), msg)
                    }
                }
            }
        }
    }

    private fun groups(subsets: List<String> = compared) = subsets.flatMap { subset -> (listOf(PeerFigures.OVERALL) + PeerFigures.subsets.getValue(subset).groups).map { group -> subset to group } }

    private fun compare(label: String, metric: String, results: () -> Map<String, List<TrialResult>>): List<DynamicTest> =
        groups().map { (subset, group) ->
            DynamicTest.dynamicTest("$label $subset $group") {
                assumeTrue(PeerFigures.data != null, "no ../shared/data beside the repository: not evaluated")
                val trials = results().getValue(subset).filter { group == PeerFigures.OVERALL || PeerFigures.group(subset, it.trial) == group }
                assertTrue(trials.isNotEmpty(), "no $group trial in $subset")
                val ours = trials.map { it.error.totalDeg }.average()
                val vqf = trials.map { PeerFigures.of("$subset/${it.trial}", metric) }.average()
                println(String.format(Locale.ROOT, "%s %s %s: %.2f° (VQF %.2f°)", label, subset, group, ours, vqf))
                val measured = BEHIND["$label $subset $group"]
                if (measured != null) {
                    // Still behind VQF here: the measured figure holds, so a regression fails.
                    assertTrue(ours <= measured * (1 + BEHIND_MARGIN), String.format(Locale.ROOT, "%s %s %s (%d trials): mean total RMSE %.2f°, measured %.2f° (+%.0f %% allowed; VQF %.2f°)", label, subset, group, trials.size, ours, measured, 100 * BEHIND_MARGIN, vqf))
                    return@dynamicTest
                }
                assertTrue(ours <= vqf * (1 + PeerFigures.RMSE_MARGIN), String.format(Locale.ROOT, "%s %s %s (%d trials): mean total RMSE %.2f°, VQF %.2f° (behind by %.2f°, %.0f %%)", label, subset, group, trials.size, ours, vqf, ours - vqf, 100 * (ours - vqf) / vqf))
            }
        }

    private companion object {
        /**
         * The groups where the defaults are still behind VQF ("causal|offline subset group"), with the defaults'
         * measured mean total RMSE there, degrees (docs/ACCURACY.md, "Not done yet").
         */
        val BEHIND = mapOf(
            "causal advio-subset metro" to 37.49,
        )

        /** How far above the better of VQF 9D and 6D a venue may be with the trust (issue's target). */
        const val INDOOR_OF_BEST = 0.10

        /** How far above its measured figure a [BEHIND] group may be (noise of a rebuild, not a regression). */
        const val BEHIND_MARGIN = 0.02

        /** The READMEs' VQF rows (by how the row starts) and the committed metric each gives. */
        val PUBLISHED_ROWS = listOf("| VQF 9D" to PeerFigures.TOTAL_RMSE, "| VQF offline" to PeerFigures.OFFLINE_TOTAL_RMSE, "| VQF 6D" to PeerFigures.TOTAL_RMSE_6D)

        /** How far a mean of committed figures (two decimals each) may be from the README's, degrees. */
        const val PUBLISHED_TOLERANCE_DEG = 0.015

        /** The cells of a Markdown table row, trimmed. */
        fun cells(line: String): List<String> = line.trim().removePrefix("|").removeSuffix("|").split('|').map { it.trim() }

        /** The first number in [cell] ("16.42 (18.19)" → 16.42, "in the hand (8)" → 8.0, "all 33" → 33.0), or null. */
        fun firstNumber(cell: String): Double? = Regex("""\d+(\.\d+)?""").find(cell)?.value?.toDouble()
    }
}
