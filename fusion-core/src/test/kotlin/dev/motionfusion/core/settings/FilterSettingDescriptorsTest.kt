package dev.motionfusion.core.settings

import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.session.SessionMetadata
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import java.lang.reflect.Modifier

class FilterSettingDescriptorsTest {
    @Test
    fun `every property of FilterSettings has exactly one descriptor`() {
        val fields = FilterSettings::class.java.declaredFields.filter { !Modifier.isStatic(it.modifiers) }.map { it.name }
        assertEquals(fields, FilterSettingDescriptors.all.map { it.name })
        assertEquals(FilterSettingDescriptors.all.size, FilterSettingDescriptors.all.map { it.jsonKey }.toSet().size)
    }

    @Test
    fun `each descriptor reads and writes its own property`() {
        val d = FilterSettings()
        for (s in FilterSettingDescriptors.all) {
            val other: Any = when (s.kind) {
                SettingKind.NUMBER -> (s.value(d) as Double).let { if (it == 0.0) 0.25 else it * 0.5 }
                SettingKind.BOOLEAN -> !(s.value(d) as Boolean)
                SettingKind.CHOICE -> s.choices.first { it != s.value(d) }
            }
            val changed = s.with(d, other)
            assertNotEquals(d, changed, s.name)
            assertEquals(other, s.value(changed), s.name)
            // Only this property changed.
            for (t in FilterSettingDescriptors.all) if (t !== s) assertEquals(t.value(d), t.value(changed), "${s.name} changed ${t.name}")
            assertEquals(changed, s.withText(d, other.toString()), s.name)
        }
    }

    @Test
    fun `bad values are refused with the setting's name`() {
        val d = FilterSettings()
        assertEquals(0.05, FilterSettingDescriptors.apply(d, "beta=0.05").beta)
        for (bad in listOf("beta=x", "beta=-1", "restBiasEstimation=yes", "mode=6D", "gamma=1", "beta")) {
            assertThrows<IllegalArgumentException>(bad) { FilterSettingDescriptors.apply(d, bad) }
        }
        val e = assertThrows<IllegalArgumentException> { FilterSettingDescriptors.apply(d, "headingGain=abc") }
        assertTrue("headingGain" in e.message!!)
    }

    @Test
    fun `stored settings written before a mechanism existed replay with it off`() {
        val json = """{"format_version":${SessionMetadata.FORMAT_VERSION},"device":{},"filter_settings":{"beta":0.05,"mag_disturbance_rejection":true}}"""
        val s = dev.motionfusion.core.session.MetadataJson.parse(json, "meta.json").filterSettings!!
        assertEquals(0.05, s.beta)
        assertTrue(s.magDisturbanceRejection)
        assertEquals(
            listOf(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
            listOf(s.headingGain, s.headingRecoveryTime, s.motionBiasGain, s.magNewFieldTime, s.accLowPassTime, s.gyroSaturation),
        )
        // A member that is present is taken as it is; one absent without a value of its time takes the default.
        assertEquals(FilterSettings().restMinTime, s.restMinTime)
        val back = dev.motionfusion.core.session.MetadataJson.settings(FilterSettings())
        assertEquals(FilterSettingDescriptors.all.map { it.jsonKey }, back.keys.toList())
    }

    @Test
    fun `a screen's ranges hold the defaults and are accepted by the settings`() {
        for (d in FilterSettingDescriptors.all) {
            assertTrue(d.title.isNotBlank(), d.name)
            if (d.kind != SettingKind.NUMBER) {
                assertEquals(null, d.range, d.name)
                continue
            }
            val r = requireNotNull(d.range) { "${d.name} has no range" }
            val default = d.default as Double
            assertTrue(default in r, "${d.name}: default $default outside $r")
            // Both ends are values the settings take, so a slider can never offer a refused one.
            d.with(FilterSettings(), r.start)
            d.with(FilterSettings(), r.endInclusive)
            // "0 turns it off" needs 0 to be a value of the range, and 0 accepted.
            if (d.zeroDisables) assertEquals(0.0, r.start, d.name)
        }
        assertEquals(setOf("zeta", "magNewFieldTime", "magNewFieldMinGyro", "magResumeTime", "magRejectionFactor", "magFirstFieldTime", "magUndisturbedTime", "inclinationRecoveryBeta", "recoveryAngle", "accLowPassTime", "gyroSaturation", "headingGain", "headingRecoveryTime", "motionBiasGain"),
            FilterSettingDescriptors.all.filter { it.zeroDisables }.map { it.name }.toSet())
        assertEquals(SettingGroup.entries.toSet(), FilterSettingDescriptors.all.map { it.group }.toSet())
    }
}
