"""The column names of the ANSUR II public data files (Gordon et al. 2014, NATICK/TR-15/007;
the header of ANSUR_II_MALE_Public.csv and ANSUR_II_FEMALE_Public.csv, which are the same):
what a ``--measurements`` row copied from the survey may hold. Any other column is a
misspelling or a file of another kind."""

SURVEY_COLUMNS: tuple[str, ...] = (
    'SubjectId', 'abdominalextensiondepthsitting', 'acromialheight', 'acromionradialelength',
    'anklecircumference', 'axillaheight', 'balloffootcircumference', 'balloffootlength',
    'biacromialbreadth', 'bicepscircumferenceflexed', 'bicristalbreadth', 'bideltoidbreadth',
    'bimalleolarbreadth', 'bitragionchinarc', 'bitragionsubmandibulararc', 'bizygomaticbreadth',
    'buttockcircumference', 'buttockdepth', 'buttockheight', 'buttockkneelength',
    'buttockpopliteallength', 'calfcircumference', 'cervicaleheight', 'chestbreadth',
    'chestcircumference', 'chestdepth', 'chestheight', 'crotchheight', 'crotchlengthomphalion',
    'crotchlengthposterioromphalion', 'earbreadth', 'earlength', 'earprotrusion',
    'elbowrestheight', 'eyeheightsitting', 'footbreadthhorizontal', 'footlength',
    'forearmcenterofgriplength', 'forearmcircumferenceflexed', 'forearmforearmbreadth',
    'forearmhandlength', 'functionalleglength', 'handbreadth', 'handcircumference',
    'handlength', 'headbreadth', 'headcircumference', 'headlength', 'heelanklecircumference',
    'heelbreadth', 'hipbreadth', 'hipbreadthsitting', 'iliocristaleheight',
    'interpupillarybreadth', 'interscyei', 'interscyeii', 'kneeheightmidpatella',
    'kneeheightsitting', 'lateralfemoralepicondyleheight', 'lateralmalleolusheight',
    'lowerthighcircumference', 'mentonsellionlength', 'neckcircumference',
    'neckcircumferencebase', 'overheadfingertipreachsitting', 'palmlength', 'poplitealheight',
    'radialestylionlength', 'shouldercircumference', 'shoulderelbowlength', 'shoulderlength',
    'sittingheight', 'sleevelengthspinewrist', 'sleeveoutseam', 'span', 'stature',
    'suprasternaleheight', 'tenthribheight', 'thighcircumference', 'thighclearance',
    'thumbtipreach', 'tibialheight', 'tragiontopofhead', 'trochanterionheight',
    'verticaltrunkcircumferenceusa', 'waistbacklength', 'waistbreadth', 'waistcircumference',
    'waistdepth', 'waistfrontlengthsitting', 'waistheightomphalion', 'weightkg',
    'wristcircumference', 'wristheight', 'Gender', 'Date', 'Installation', 'Component',
    'Branch', 'PrimaryMOS', 'SubjectsBirthLocation', 'SubjectNumericRace', 'Ethnicity',
    'DODRace', 'Age', 'Heightin', 'Weightlbs', 'WritingPreference',
)
