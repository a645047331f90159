package dev.motionfusion.core.settings

import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.session.SessionMetadata
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertNull
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
                SettingKind.NUMBER -> (s.value(d) as Double?)?.let { it * 0.5 } ?: 0.25
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
            listOf(null, null, null, null, null, null),
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
            val default = d.default as Double?
            assertTrue(default == null && d.zeroDisables || default!! in r, "${d.name}: default $default outside $r")
            // Both ends are values the settings take, so a slider can never offer a refused one.
            d.with(FilterSettings(), r.start)
            d.with(FilterSettings(), r.endInclusive)
            // "0 turns it off" needs 0 to be a value of the range, and 0 accepted.
            if (d.zeroDisables) assertEquals(0.0, r.start, d.name)
        }
        assertEquals(setOf("zeta", "magNewFieldTime", "magNewFieldMinGyro", "magResumeTime", "magRejectionFactor", "magFirstFieldTime", "magUndisturbedTime", "magTrustSpread", "hardIronThreshold", "hardIronTime", "inclinationRecoveryBeta", "recoveryAngle", "accLowPassTime", "gyroSaturation", "headingGain", "headingRecoveryTime", "motionBiasGain"),
            FilterSettingDescriptors.all.filter { it.zeroDisables }.map { it.name }.toSet())
        assertEquals(SettingGroup.entries.toSet(), FilterSettingDescriptors.all.map { it.group }.toSet())
    }

    private val offable = FilterSettingDescriptors.all.filter { it.zeroDisables }

    @Test
    fun `a mechanism is off by null, and 0 is refused so off has one form`() {
        assertEquals(17, offable.size)
        for (d in offable) {
            val on = d.with(FilterSettings(), d.range!!.endInclusive / 10)
            assertNull(d.value(d.with(on, null)), d.name)
            assertEquals(d.with(on, null), d.with(on, 0.0), d.name)
        }
        for (zero in listOf({ FilterSettings(zeta = 0.0) }, { FilterSettings(magTrustSpread = 0.0) }, { FilterSettings(gyroSaturation = 0.0) }, { FilterSettings(recoveryAngle = 0.0) })) {
            val e = assertThrows<IllegalArgumentException> { zero() }
            assertTrue("null for off" in e.message!!, e.message)
        }
        assertNull(FilterSettings(headingGain = null).headingGain)
    }

    @Test
    fun `NAME=off and NAME=0 turn a mechanism off, as every command written before`() {
        val d = FilterSettings()
        for (s in offable) {
            val on = s.with(d, s.range!!.endInclusive / 10)
            for (text in listOf("off", "OFF", " off ", "0", "0.0")) assertNull(s.value(FilterSettingDescriptors.apply(on, "${s.name}=$text")), "${s.name}=$text")
        }
        assertEquals(0.01, FilterSettingDescriptors.apply(d, "magTrustSpread=0.01").magTrustSpread)
        assertNull(FilterSettingDescriptors.apply(FilterSettings(magTrustSpread = 0.01), "magTrustSpread=off").magTrustSpread)
        assertNull(FilterSettingDescriptors.apply(d, "gyroSaturation=off").gyroSaturation)
        // A setting that cannot be off takes no "off"; 0 stays a value where it is one.
        val e = assertThrows<IllegalArgumentException> { FilterSettingDescriptors.apply(d, "beta=off") }
        assertTrue("beta" in e.message!!, e.message)
        assertEquals(0.0, FilterSettingDescriptors.apply(d, "restMinTime=0").restMinTime)
    }

    @Test
    fun `a meta json written with 0 for off reads back to the same settings and is written so again`() {
        // filter_settings as the writer before null-for-off wrote them: every mechanism off as 0.
        val old = """{"format_version":${SessionMetadata.FORMAT_VERSION},"device":{},"filter_settings":{"mode":"MARG","beta":0.05,"zeta":0.0,
            |"mag_new_field_time_s":0.0,"mag_new_field_min_gyro_rad_s":0.0,"mag_resume_time_s":0.0,"mag_rejection_factor":0.0,
            |"mag_first_field_time_s":0.0,"mag_undisturbed_time_s":0.0,"mag_trust_spread":0.0,"inclination_recovery_beta":0.0,
            |"recovery_angle_rad":0.0,"acc_low_pass_time_s":0,"gyro_saturation_rad_s":0.0,"heading_gain_1_s":0.0,
            |"heading_recovery_time_s":0.0,"motion_bias_gain_rad_s2":0.0}}""".trimMargin()
        val s = dev.motionfusion.core.session.MetadataJson.parse(old, "meta.json").filterSettings!!
        val expected = FilterSettings(
            beta = 0.05, zeta = null, magNewFieldTime = null, magNewFieldMinGyro = null, magResumeTime = null, magRejectionFactor = null,
            magFirstFieldTime = null, magUndisturbedTime = null, magTrustSpread = null, inclinationRecoveryBeta = null, recoveryAngle = null,
            accLowPassTime = null, gyroSaturation = null, headingGain = null, headingRecoveryTime = null, motionBiasGain = null,
            // Written before the hard-iron estimate existed: absent, so off (the replay is the filter that ran then).
            hardIronThreshold = null, hardIronTime = null,
        )
        assertEquals(expected, s)
        // Written again, off is 0 as before, so an older reader takes these files too; "off" and null read as off as well.
        val written = dev.motionfusion.core.session.MetadataJson.settings(s)
        for (d in offable) assertEquals(0.0, written[d.jsonKey], d.name)
        assertEquals(0.05, written["beta"])
        val spelled = """{"format_version":${SessionMetadata.FORMAT_VERSION},"device":{},"filter_settings":{"mag_trust_spread":"off","gyro_saturation_rad_s":"off"}}"""
        val t = dev.motionfusion.core.session.MetadataJson.parse(spelled, "meta.json").filterSettings!!
        assertNull(t.magTrustSpread)
        assertNull(t.gyroSaturation)
    }
}
