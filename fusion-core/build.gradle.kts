// fusion-core: pure Kotlin on the JVM, no android.* (fusion-core/pom.xml).
plugins {
    alias(libs.plugins.kotlin.jvm)
}

kotlin {
    jvmToolchain(17)
    // As -Xexplicit-api=strict in fusion-core/pom.xml (main sources only).
    explicitApi()
}

sourceSets {
    main { kotlin.srcDirs("src/main/kotlin") }
    test { kotlin.srcDirs("src/test/kotlin") }
}

dependencies {
    implementation(libs.kotlin.stdlib)
    testImplementation(platform(libs.junit.bom))
    testImplementation(libs.junit.jupiter)
    // The real SensorManager, to test the ports against.
    testImplementation(libs.android.all)
}

tasks.test {
    useJUnitPlatform()
}
