package dev.motionfusion.core.eval

import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.replay.OfflineSettings
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.DynamicTest
import org.junit.jupiter.api.TestFactory
import java.util.Locale

/**
 * The default settings against VQF on the two evaluation subsets beside the repository
 * (../shared/data/broad-subset and tyrex-subset; never copied into it): on each subset, overall
 * and in each group (undisturbed, disturbed), the project's mean total RMSE (BROAD's metric) is
 * at most [PeerFigures.RMSE_MARGIN] (5 %) above VQF's on the same trials, VQF's figures being
 * those committed in peers/vqf.csv ([PeerFigures]): the causal replay against VQF's real-time
 * filter, the offline replay (default [OfflineSettings]) against `vqf.offlineVQF`. Skipped when
 * the data is absent; a trial missing from the data or from the figures fails.
 */
class SubsetAccuracyTest {
    private val subsets = mapOf("broad-subset" to 7, "tyrex-subset" to 14)

    private fun results(offline: OfflineSettings?): Map<String, List<TrialResult>> =
        subsets.mapValues { (name, trials) ->
            Evaluation.evaluateAll(listOf(PeerFigures.data!!.resolve(name).toFile()), FilterSettings(), offline).also {
                assertEquals(trials, it.size, "trials in $name")
            }
        }

    private val causal by lazy { results(null) }
    private val offline by lazy { results(OfflineSettings()) }

    @TestFactory
    fun `defaults within 5 percent of VQF on each subset overall and in each group`(): List<DynamicTest> =
        compare("causal", PeerFigures.TOTAL_RMSE) { causal }

    @TestFactory
    fun `offline defaults within 5 percent of VQF offline on each subset overall and in each group`(): List<DynamicTest> =
        compare("offline", PeerFigures.OFFLINE_TOTAL_RMSE) { offline }

    private fun compare(label: String, metric: String, results: () -> Map<String, List<TrialResult>>): List<DynamicTest> =
        subsets.keys.flatMap { subset -> listOf("overall", "undisturbed", "disturbed").map { group -> subset to group } }.map { (subset, group) ->
            DynamicTest.dynamicTest("$label $subset $group") {
                assumeTrue(PeerFigures.data != null, "no ../shared/data beside the repository: not evaluated")
                val trials = results().getValue(subset).filter { group == "overall" || PeerFigures.group(it.trial) == group }
                assertTrue(trials.isNotEmpty(), "no $group trial in $subset")
                val ours = trials.map { it.error.totalDeg }.average()
                val vqf = trials.map { PeerFigures.of("$subset/${it.trial}", metric) }.average()
                println(String.format(Locale.ROOT, "%s %s %s: %.2f° (VQF %.2f°)", label, subset, group, ours, vqf))
                assertTrue(ours <= vqf * (1 + PeerFigures.RMSE_MARGIN), String.format(Locale.ROOT, "%s %s %s (%d trials): mean total RMSE %.2f°, VQF %.2f° (behind by %.2f°, %.0f %%)", label, subset, group, trials.size, ours, vqf, ours - vqf, 100 * (ours - vqf) / vqf))
            }
        }
}
